// STL input (ASCII, binary) and the errors for bad files and bad triangles.
#include "reference_file.h"

#include "stl_reader.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <limits>

namespace dembridge::mesh::test {
namespace {

std::string temp_file(const std::string &name, const std::string &content)
{
  const std::string path = ::testing::TempDir() + "dembridge_mesh_" + name;
  std::ofstream(path, std::ios::binary) << content;
  return path;
}

std::string ascii_facets(const std::string &body) { return "solid t\n" + body + "endsolid t\n"; }

std::string facet(const std::string &v0, const std::string &v1, const std::string &v2)
{
  return "facet normal 0 0 1\n outer loop\n  vertex " + v0 + "\n  vertex " + v1 + "\n  vertex " + v2 +
         "\n endloop\nendfacet\n";
}

void put_u32(std::string &s, std::uint32_t v)
{
  for (int b = 0; b < 4; ++b) s.push_back(char((v >> (8 * b)) & 0xff));
}
void put_f32(std::string &s, float f)
{
  std::uint32_t u;
  std::memcpy(&u, &f, 4);
  put_u32(s, u);
}

std::string binary_stl(const std::vector<std::array<float, 9>> &tris)
{
  std::string s(80, ' ');
  s.replace(0, 5, "solid");  // binary files may start with 'solid' too
  put_u32(s, std::uint32_t(tris.size()));
  for (const auto &t : tris) {
    for (int k = 0; k < 3; ++k) put_f32(s, 0.0f);
    for (float f : t) put_f32(s, f);
    s += std::string(2, '\0');
  }
  return s;
}

std::string error_of(const std::string &path)
{
  try {
    TriangleMesh m(read_stl(path));
  } catch (const MeshError &e) {
    return e.what();
  }
  return "";
}

TEST(StlReader, AsciiVerticesAreParsedAsDoublesAndFacetNormalsIgnored)
{
  const auto tris = read_stl(temp_file("a.stl", ascii_facets(facet("0.1 0.2 0.3", "1.1 0.2 0.3", "0.1 1.2 0.3"))));
  ASSERT_EQ(tris.size(), 1u);
  EXPECT_EQ(tris[0][0][0], 0.1);
  EXPECT_EQ(tris[0][2][1], 1.2);
  const TriangleMesh m(tris);  // normal from the node order (+z), not from the file's
  EXPECT_EQ(m.normal(0)[2], 1.0);
}

TEST(StlReader, BinaryVerticesAreFloatsWidenedToDouble)
{
  const float a = 0.1f, b = 1.3f;
  const std::string path = temp_file("b.stl", binary_stl({{a, 0.f, 0.f, b, 0.f, 0.f, a, b, 0.5f},
                                                          {b, 0.f, 0.f, b, b, 0.f, a, b, 0.5f}}));
  const auto tris = read_stl(path);
  ASSERT_EQ(tris.size(), 2u);
  EXPECT_EQ(tris[0][0][0], double(a));
  EXPECT_NE(tris[0][0][0], 0.1);  // not the decimal 0.1: binary and ASCII meshes differ (spec §4.1)
  EXPECT_EQ(tris[1][1][1], double(b));
  EXPECT_EQ(tris[0][2][2], 0.5);
  const TriangleMesh m(tris);
  EXPECT_TRUE(m.are_node_neighbors(0, 1));
}

TEST(StlReader, BinaryAndAsciiPlateGiveTheSameTopology)
{
  const auto ascii = read_stl(data_path("box.stl"));
  std::vector<std::array<float, 9>> f;
  for (const auto &t : ascii) {
    std::array<float, 9> v;
    for (int k = 0; k < 3; ++k)
      for (int d = 0; d < 3; ++d) v[3 * k + d] = float(t[k][d]);
    f.push_back(v);
  }
  const TriangleMesh a(ascii), b(read_stl(temp_file("box.bin.stl", binary_stl(f))));
  ASSERT_EQ(a.size(), b.size());
  for (int t = 0; t < a.size(); ++t)
    for (int k = 0; k < 3; ++k) {
      EXPECT_EQ(a.edge_active(t, k), b.edge_active(t, k));
      EXPECT_EQ(a.corner_active(t, k), b.corner_active(t, k));
    }
}

TEST(StlReader, MissingFileNamesTheFile)
{
  EXPECT_NE(error_of("/nonexistent/dir/wall.stl").find("cannot open STL file '/nonexistent/dir/wall.stl'"), std::string::npos);
}

TEST(StlReader, MalformedAsciiNamesTheLine)
{
  EXPECT_NE(error_of(temp_file("m1.stl", ascii_facets(facet("0 0 0", "1 0 x", "0 1 0")))).find("line 5: 'x' is not a number"),
            std::string::npos);
  EXPECT_NE(error_of(temp_file("m2.stl", "solid t\nfacet normal 0 0 1\n outer loop\n  vertex 0 0 0\n  vertex 1 0 0\n endloop\nendfacet\nendsolid\n"))
                .find("2 vertices"),
            std::string::npos);
  EXPECT_NE(error_of(temp_file("m3.stl", "solid t\nfacet normal 0 0 1\n outer loop\n  vertex 0 0 0\n")).find("ends inside a facet"),
            std::string::npos);
  EXPECT_NE(error_of(temp_file("m4.stl", "hello world\n")).find("unexpected keyword 'hello'"), std::string::npos);
  EXPECT_NE(error_of(temp_file("m5.stl", "solid empty\nendsolid empty\n")).find("has no facets"), std::string::npos);
  EXPECT_NE(error_of(temp_file("m6.stl", "")).find("is empty"), std::string::npos);
  EXPECT_NE(error_of(temp_file("m7.stl", ascii_facets(facet("0 0", "1 0 0", "0 1 0")))).find("vertex needs 3 coordinates"),
            std::string::npos);
}

TEST(StlReader, TruncatedOrMiscountedBinaryIsReportedAsBinary)
{
  const std::string two = binary_stl({{0, 0, 0, 1, 0, 0, 0, 1, 0}, {1, 0, 0, 1, 1, 0, 0, 1, 0}});
  std::string msg = error_of(temp_file("cut.stl", two.substr(0, two.size() - 20)));
  EXPECT_NE(msg.find("binary STL file '"), std::string::npos) << msg;
  EXPECT_NE(msg.find("cut.stl' (164 bytes): the header gives 2 facets, which take 84 + 50*2 = 184 bytes; the file ends inside "
                     "facet 2 (truncated, or a wrong facet count)"),
            std::string::npos)
      << msg;
  EXPECT_EQ(msg.find("ASCII"), std::string::npos) << msg;
  std::string miscounted = two;
  miscounted[80] = 3;  // the header claims 3 facets
  msg = error_of(temp_file("count.stl", miscounted));
  EXPECT_NE(msg.find("the header gives 3 facets, which take 84 + 50*3 = 234 bytes; the file ends inside facet 3 (truncated, or a "
                     "wrong facet count); the size fits 2 facets"),
            std::string::npos)
      << msg;
  miscounted[80] = 1;
  msg = error_of(temp_file("count1.stl", miscounted));
  EXPECT_NE(msg.find("the header gives 1 facets, which take 84 + 50*1 = 134 bytes; 50 bytes follow the last facet"), std::string::npos) << msg;
  msg = error_of(temp_file("short.stl", std::string("solid\0\0", 7)));
  EXPECT_NE(msg.find("(7 bytes): shorter than the 84-byte header"), std::string::npos) << msg;
}

TEST(StlReader, FolderIsNotAnStlFile)
{
  const std::string msg = error_of(::testing::TempDir());
  EXPECT_NE(msg.find("' is a directory, expected an STL file"), std::string::npos) << msg;
}

TEST(StlReader, FourthNumberOnAVertexLineIsAnError)
{
  const std::string msg = error_of(temp_file("v4.stl", ascii_facets(facet("0 0 0", "1 0 0 7", "0 1 0"))));
  EXPECT_NE(msg.find("v4.stl' line 5: '7' after the 3 coordinates of a vertex (expected 'vertex x y z')"), std::string::npos) << msg;
}

TEST(MeshValidation, HugeCoordinatesOverflowNotColinear)
{
  const std::string msg = error_of(temp_file("huge.stl", ascii_facets(facet("0 0 0", "1e300 0 0", "0 1e300 0"))));
  EXPECT_NE(msg.find("triangle 1 (file order): the length of edge 1 overflows double precision (coordinates up to 1e+300); "
                     "expected coordinates well below 1e150"),
            std::string::npos)
      << msg;
  EXPECT_EQ(msg.find("colinear"), std::string::npos) << msg;
}

TEST(MeshValidation, PrecisionIsPrintedReadably)
{
  MeshOptions opt;
  opt.precision = 1e-8;
  std::string msg;
  try {
    TriangleMesh m({TriangleNodes{Vec3{0, 0, 0}, Vec3{1e-9, 0, 0}, Vec3{0, 1, 0}}}, opt);
  } catch (const MeshError &e) {
    msg = e.what();
  }
  EXPECT_NE(msg.find("triangle 1 (file order) is degenerate: edge 1 is shorter than the precision 1e-08"), std::string::npos) << msg;
}

TEST(MeshValidation, NanTriangleIsRejected)
{
  const std::string msg = error_of(temp_file("nan.stl", ascii_facets(facet("0 0 0", "1 0 0", "0 1 0") + facet("0 0 0", "nan 0 0", "0 1 0"))));
  EXPECT_NE(msg.find("triangle 2 (file order) has a non-finite"), std::string::npos) << msg;
}

TEST(MeshValidation, DegenerateTrianglesAreRejected)
{
  std::string msg = error_of(temp_file("deg1.stl", ascii_facets(facet("0 0 0", "0 0 0", "0 1 0"))));
  EXPECT_NE(msg.find("triangle 1 (file order) is degenerate"), std::string::npos) << msg;
  msg = error_of(temp_file("deg2.stl", ascii_facets(facet("0 0 0", "1 0 0", "2 0 0"))));
  EXPECT_NE(msg.find("is degenerate"), std::string::npos) << msg;
}

TEST(MeshValidation, SliverNeedsCurvatureTolerant)
{
  // angle of about 0.06 degrees at node 0: below the default limit acos(1 - 1e-5) = 0.256 degrees
  const std::vector<TriangleNodes> sliver{{Vec3{0.0, 0.0, 0.0}, Vec3{1.0, 0.0, 0.0}, Vec3{1.0, 0.001, 0.0}}};
  try {
    TriangleMesh m(sliver);
    ADD_FAILURE() << "sliver accepted";
  } catch (const MeshError &e) {
    EXPECT_NE(std::string(e.what()).find("curvature_tolerant"), std::string::npos);
  }
  MeshOptions opt;
  opt.curvature_tolerant = true;
  EXPECT_NO_THROW(TriangleMesh(sliver, opt));
}

}  // namespace
}  // namespace dembridge::mesh::test
