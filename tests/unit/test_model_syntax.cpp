// The pair_style dialects parsed into one model description (spec granular-models §1).
#include "model_syntax.h"

#include <gtest/gtest.h>

using namespace dembridge::gran;

static std::string error_of(const std::string &style, const std::vector<std::string> &args)
{
  try {
    parse_pair_style(style, args);
  } catch (const SyntaxError &e) {
    return e.what();
  }
  return "";
}

TEST(ModelSyntax, LegacyNamesSelectModels)
{
  auto d = parse_pair_style("gran/hooke", {});
  EXPECT_EQ(d.dialect, Dialect::Liggghts2x);
  EXPECT_EQ(d.contact.normal, NormalModel::Hooke);
  EXPECT_EQ(d.contact.tangential, TangentialModel::NoHistory);
  EXPECT_TRUE(d.contact.tangential_damping);
  d = parse_pair_style("gran/hertz/history/simple", {});
  EXPECT_EQ(d.contact.normal, NormalModel::HertzStiffness);
  EXPECT_EQ(d.contact.tangential, TangentialModel::History);
  EXPECT_EQ(d.contact.history_size(), 3);
}

TEST(ModelSyntax, LegacyKeywordsAnyOrderLaterWins)
{
  const auto d = parse_pair_style("gran/hooke/history",
                                  {"tangential_damping", "off", "rolling_friction", "cdt", "cohesion", "sjkr2", "rolling_friction", "epsd"});
  EXPECT_FALSE(d.contact.tangential_damping);
  EXPECT_EQ(d.contact.rolling, RollingModel::Epsd);
  EXPECT_EQ(d.contact.cohesion, CohesionModel::Sjkr2);
  EXPECT_TRUE(d.contact.tangential_reduce);  // 2.x: cohesion always in the Coulomb limit
  EXPECT_EQ(d.contact.history_size(), 6);
}

TEST(ModelSyntax, LegacyErrorsNameTheArgument)
{
  EXPECT_NE(error_of("gran/hooke", {"foo", "on"}).find("unknown keyword 'foo'"), std::string::npos);
  EXPECT_NE(error_of("gran/hooke", {"tangential_damping", "maybe"}).find("expecting 'on' or 'off' after keyword 'tangential_damping'"),
            std::string::npos);
  EXPECT_NE(error_of("gran/hooke", {"rolling_friction"}).find("needs a value"), std::string::npos);
  EXPECT_NE(error_of("gran/hooke", {"rolling_friction", "epsd2"}).find("needs per-contact history"), std::string::npos);
  EXPECT_NE(error_of("gran/hertz/history/stiffness", {"absolute_damping", "on"}).find("not available with hertz stiffness"),
            std::string::npos);
  EXPECT_NE(error_of("gran/hooke/history/stiffness", {"viscous", "stokes"}).find("stiffness model"), std::string::npos);
  EXPECT_NE(error_of("gran/hooke", {"absolute_damping", "on"}).find("only available with the hooke stiffness"), std::string::npos);
  EXPECT_NE(error_of("gran/hooke", {"cohesion", "glue"}).find("got 'glue'"), std::string::npos);
}

TEST(ModelSyntax, HertzViscousIsIgnoredWithWarningAs2x)
{
  const auto d = parse_pair_style("gran/hertz/history", {"viscous", "stokes"});
  EXPECT_FALSE(d.contact.viscous);
  ASSERT_EQ(d.warnings.size(), 1u);
}

TEST(ModelSyntax, LammpsNumericDialectIsDetectedByTheFirstNumber)
{
  const auto d = parse_pair_style("gran/hooke/history", {"2e5", "NULL", "50", "NULL", "0.5", "0"});
  EXPECT_EQ(d.dialect, Dialect::LammpsNumeric);
  EXPECT_DOUBLE_EQ(d.numeric.kt, 2e5 * 2.0 / 7.0);
  EXPECT_DOUBLE_EQ(d.numeric.gammat, 0.0);  // dampflag 0
  EXPECT_TRUE(d.contact.lammps_formulation);
  EXPECT_NE(error_of("gran/hooke", {"2e5", "NULL", "50"}).find("expected 'Kn Kt"), std::string::npos);
  EXPECT_NE(error_of("gran/hooke", {"2e5", "NULL", "50", "NULL", "0.5", "2"}).find("dampflag must be 0 or 1"), std::string::npos);
}

TEST(ModelSyntax, Liggghts3StrictOrder)
{
  const auto d = parse_pair_style("gran", {"model", "hertz", "tangential", "history", "cohesion", "sjkr", "rolling_friction", "cdt",
                                           "tangential_reduce", "on"});
  EXPECT_EQ(d.dialect, Dialect::Liggghts3x);
  EXPECT_EQ(d.contact.normal, NormalModel::Hertz);
  EXPECT_TRUE(d.contact.tangential_reduce);
  EXPECT_EQ(parse_pair_style("gran", {"model", "hooke"}).contact.tangential, TangentialModel::None);
  EXPECT_NE(error_of("gran", {"model", "hertz", "rolling_friction", "cdt", "tangential", "history"}).find("wrong keyword order: 'tangential'"),
            std::string::npos);
  EXPECT_NE(error_of("gran", {"model", "hertz", "viscous", "on"}).find("'viscous'"), std::string::npos);
  // a setting of another model is named as such, not as a keyword-order error
  EXPECT_NE(error_of("gran", {"model", "hertz", "tangential", "history", "viscous", "on"}).find("model hertz has no viscous model"),
            std::string::npos);
  EXPECT_EQ(error_of("gran", {"model", "hertz", "viscous", "on"}).find("keyword order"), std::string::npos);
  EXPECT_NE(error_of("gran", {"model", "hertz", "absolute_damping", "on"}).find("model hooke/stiffness"), std::string::npos);
  EXPECT_NE(error_of("gran", {"model", "hooke", "torsionTorque", "on"}).find("rolling friction"), std::string::npos);
  EXPECT_NE(error_of("gran", {"model", "hooke", "tangential_damping", "maybe"}).find("'maybe'"), std::string::npos);
}
