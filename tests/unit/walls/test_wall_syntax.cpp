#include "wall_syntax.h"

#include <gtest/gtest.h>

using namespace dembridge;
using namespace dembridge::walls;

namespace {
std::vector<std::string> words(const std::string &s)
{
  std::vector<std::string> w;
  std::size_t a = 0;
  while (a < s.size()) {
    auto b = s.find(' ', a);
    if (b == std::string::npos) b = s.size();
    if (b > a) w.push_back(s.substr(a, b - a));
    a = b + 1;
  }
  return w;
}
WallSpec parse(const std::string &style, const std::string &args) { return parse_wall_gran(style, words(args), "fix w wall/gran"); }
std::string error_of(const std::string &style, const std::string &args)
{
  try {
    parse(style, args);
  } catch (const gran::SyntaxError &e) {
    return e.what();
  }
  return "";
}
}  // namespace

TEST(WallSyntax, Liggghts3xPrimitive)
{
  const auto s = parse("wall/gran", "model hooke tangential history cohesion sjkr2 rolling_friction cdt primitive type 2 zplane 0.5");
  EXPECT_FALSE(s.is_mesh);
  EXPECT_EQ(s.primitive.wall_type, 2);
  EXPECT_EQ(s.primitive.axis, 2);
  EXPECT_EQ(s.primitive.pos, 0.5);
  EXPECT_EQ(s.model.contact.normal, gran::NormalModel::Hooke);
  EXPECT_EQ(s.model.contact.cohesion, gran::CohesionModel::Sjkr2);
  EXPECT_EQ(s.model.contact.rolling, gran::RollingModel::Cdt);
  EXPECT_FALSE(s.model.contact.tangential_reduce);
  EXPECT_FALSE(s.model.contact.legacy_2x_expressions);
}

TEST(WallSyntax, CylinderAndShear)
{
  const auto s = parse("wall/gran", "model hertz tangential history primitive type 1 ycylinder 0.02 0.001 -0.002 shear y 0.3");
  EXPECT_EQ(s.primitive.shape, PrimitiveWall::Shape::Cylinder);
  EXPECT_EQ(s.primitive.axis, 1);
  EXPECT_EQ(s.primitive.radius, 0.02);
  EXPECT_EQ(s.primitive.c1, 0.001);
  EXPECT_EQ(s.primitive.c2, -0.002);
  EXPECT_EQ(s.shear_dim, 1);
  EXPECT_EQ(s.shear_v, 0.3);
}

TEST(WallSyntax, Mesh)
{
  const auto s = parse("wall/gran", "model hertz mesh n_meshes 2 meshes a b store_force no");
  EXPECT_TRUE(s.is_mesh);
  ASSERT_EQ(s.mesh_ids.size(), 2u);
  EXPECT_EQ(s.mesh_ids[1], "b");
  EXPECT_EQ(s.model.contact.tangential, gran::TangentialModel::None);  // no 'tangential': frictionless, as 3.8
}

TEST(WallSyntax, Legacy2xNamesMapToThePairModels)
{
  const auto s = parse("wall/gran/hertz/history", "primitive type 1 zplane 0 rolling_friction epsd cohesion sjkr");
  EXPECT_EQ(s.model.contact.normal, gran::NormalModel::Hertz);
  EXPECT_EQ(s.model.contact.tangential, gran::TangentialModel::History);
  EXPECT_EQ(s.model.contact.rolling, gran::RollingModel::Epsd);
  EXPECT_TRUE(s.model.contact.tangential_reduce);  // 2.x: cohesion always inside the limits (spec §11)
  EXPECT_TRUE(s.model.contact.legacy_2x_expressions);
  const auto h = parse("wall/gran/hooke", "mesh n_meshes 1 meshes cad");
  EXPECT_EQ(h.model.contact.tangential, gran::TangentialModel::NoHistory);
}

TEST(WallSyntax, LammpsSyntaxIsRecognised)
{
  EXPECT_TRUE(is_lammps_wall_syntax("wall/gran", words("hooke 2500 NULL 3000 NULL 0.4 1 zplane 0 NULL")));
  EXPECT_FALSE(is_lammps_wall_syntax("wall/gran", words("model hooke primitive type 1 zplane 0")));
  EXPECT_FALSE(is_lammps_wall_syntax("wall/gran/hooke/history", words("primitive type 1 zplane 0")));
}

TEST(WallSyntax, BadInputNamesTheArgument)
{
  EXPECT_NE(error_of("wall/gran", "model hertz tangential history mesh meshes cad").find("have to define 'n_meshes' before 'meshes'"),
            std::string::npos);
  EXPECT_NE(error_of("wall/gran", "model hertz primitive type 1 zplane 0 mesh n_meshes 1 meshes cad").find("'mesh' given together with 'primitive'"),
            std::string::npos);
  EXPECT_NE(error_of("wall/gran", "model hertz mesh n_meshes 1 meshes cad primitive type 1 zplane 0").find("'primitive' given together with 'mesh'"),
            std::string::npos);
  EXPECT_NE(error_of("wall/gran", "model hertz primitive type 1 wplane 0").find("unknown primitive wall 'wplane'"), std::string::npos);
  EXPECT_NE(error_of("wall/gran", "model hertz primitive type 1 zplane abc").find("expected a number"), std::string::npos);
  EXPECT_NE(error_of("wall/gran", "model hertz primitive type x zplane 0").find("expected an integer"), std::string::npos);
  EXPECT_NE(error_of("wall/gran", "model hertz primitive type 1 zcylinder 0 0 0").find("must be > 0"), std::string::npos);
  EXPECT_NE(error_of("wall/gran", "model hertz tangential history").find("no wall given"), std::string::npos);
  EXPECT_NE(error_of("wall/gran", "model hertz mesh n_meshes 2 meshes a").find("expects 2 mesh fix IDs"), std::string::npos);
  // a repeated mesh would act twice (twice the force); LIGGGHTS 3.8 accepts it silently
  EXPECT_NE(error_of("wall/gran", "model hertz mesh n_meshes 2 meshes cad cad").find("fix w wall/gran: mesh 'cad' is listed twice in 'meshes'"),
            std::string::npos);
  EXPECT_NE(error_of("wall/gran/hertz/history", "mesh n_meshes 3 meshes a b a").find("mesh 'a' is listed twice"), std::string::npos);
  EXPECT_NE(error_of("wall/gran", "model hertz mesh n_meshes 1 meshes a shear x 1").find("only available for primitive"),
            std::string::npos);
  EXPECT_NE(error_of("wall/gran", "model bogus primitive type 1 zplane 0").find("fix w wall/gran: unknown model 'bogus'"),
            std::string::npos);
  EXPECT_NE(error_of("wall/gran", "model hertz tangential histor primitive type 1 zplane 0").find("'histor'"), std::string::npos);
  EXPECT_NE(error_of("wall/gran/hooke/history", "primitive type 1 zplane 0 rolling_friction foo").find("rolling_friction expects"),
            std::string::npos);
  EXPECT_NE(error_of("wall/gran", "model hertz primitive type 1 zplane 0 bogus 1").find("'bogus'"), std::string::npos);
  EXPECT_NE(error_of("wall/gran", "model hertz primitive type 1 zplane 0 store_force yes").find("not supported"), std::string::npos);
  EXPECT_NE(error_of("wall/gran", "primitive type 1 zplane 0").find("expected 'model"), std::string::npos);
}
