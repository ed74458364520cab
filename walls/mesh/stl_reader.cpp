#include "stl_reader.h"

#include <cerrno>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <sstream>
#include <sys/stat.h>

namespace dembridge::mesh {

namespace {

std::string slurp(const std::string &path)
{
  // POSIX stat, not std::filesystem: the wheel keeps to the C++ library of manylinux_2_24 systems (gcc 6's)
  struct stat st;
  if (::stat(path.c_str(), &st) == 0 && S_ISDIR(st.st_mode))
    throw MeshError("STL file '" + path + "' is a directory, expected an STL file");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw MeshError("cannot open STL file '" + path + "': " + std::strerror(errno));
  std::ostringstream os;
  os << in.rdbuf();
  return os.str();
}

std::uint32_t facet_count(const std::string &bytes)
{
  std::uint32_t n = 0;
  for (int b = 3; b >= 0; --b) n = (n << 8) | static_cast<unsigned char>(bytes[80 + b]);
  return n;
}

float le_float(const char *p)
{
  std::uint32_t u = 0;
  for (int b = 3; b >= 0; --b) u = (u << 8) | static_cast<unsigned char>(p[b]);
  float f;
  std::memcpy(&f, &u, sizeof f);
  return f;
}

std::vector<TriangleNodes> parse_binary(const std::string &bytes, const std::string &path)
{
  const std::uint32_t n = facet_count(bytes);
  std::vector<TriangleNodes> tris(n);
  for (std::uint32_t t = 0; t < n; ++t) {
    const char *rec = bytes.data() + 84 + 50 * std::size_t(t) + 12;  // skip the facet normal
    for (int k = 0; k < 3; ++k)
      for (int d = 0; d < 3; ++d) tris[t][k][d] = double(le_float(rec + 12 * k + 4 * d));
  }
  if (tris.empty()) throw MeshError("binary STL file '" + path + "' has no facets");
  return tris;
}

std::vector<TriangleNodes> parse_ascii(const std::string &text, const std::string &path)
{
  std::istringstream in(text);
  std::string line;
  int lineno = 0;
  std::vector<TriangleNodes> tris;
  TriangleNodes cur{};
  int nvert = 0;
  bool in_facet = false, in_loop = false, seen_solid = false;
  auto fail = [&](const std::string &what) {
    throw MeshError("malformed ASCII STL file '" + path + "' line " + std::to_string(lineno) + ": " + what);
  };
  while (std::getline(in, line)) {
    ++lineno;
    std::istringstream ls(line);
    std::string word;
    if (!(ls >> word)) continue;
    if (word == "solid") {
      seen_solid = true;
    } else if (word == "facet") {
      if (!seen_solid) fail("'facet' before 'solid'");
      if (in_facet) fail("'facet' inside a facet (missing 'endfacet')");
      std::string normal;
      if (!(ls >> normal) || normal != "normal") fail("expected 'facet normal nx ny nz'");
      in_facet = true;
      nvert = 0;
    } else if (word == "outer") {
      std::string loop;
      if (!in_facet || !(ls >> loop) || loop != "loop") fail("expected 'outer loop' inside a facet");
      in_loop = true;
    } else if (word == "vertex") {
      if (!in_loop) fail("'vertex' outside 'outer loop'");
      if (nvert == 3) fail("more than 3 vertices in a facet");
      for (int d = 0; d < 3; ++d) {
        std::string tok;
        if (!(ls >> tok)) fail("vertex needs 3 coordinates");
        char *end = nullptr;
        const double v = std::strtod(tok.c_str(), &end);
        if (end == tok.c_str() || *end != '\0') fail("'" + tok + "' is not a number");
        cur[nvert][d] = v;
      }
      if (std::string extra; ls >> extra)
        fail("'" + extra + "' after the 3 coordinates of a vertex (expected 'vertex x y z')");
      ++nvert;
    } else if (word == "endloop") {
      if (!in_loop) fail("'endloop' without 'outer loop'");
      in_loop = false;
    } else if (word == "endfacet") {
      if (!in_facet || in_loop) fail("'endfacet' without a complete facet");
      if (nvert != 3) fail("a facet has " + std::to_string(nvert) + " vertices, expected 3");
      tris.push_back(cur);
      in_facet = false;
    } else if (word == "endsolid") {
      if (in_facet) fail("'endsolid' inside a facet");
      seen_solid = false;
    } else {
      fail("unexpected keyword '" + word + "'");
    }
  }
  if (in_facet) fail("file ends inside a facet");
  if (tris.empty()) throw MeshError("STL file '" + path + "' has no facets");
  return tris;
}

// ASCII STL is text: no control bytes but whitespace (a binary facet holds NUL bytes at the latest
// in its attribute count).
bool looks_like_text(const std::string &bytes)
{
  for (unsigned char c : bytes)
    if ((c < 0x20 && c != '\t' && c != '\n' && c != '\r' && c != '\v' && c != '\f') || c == 0x7f) return false;
  return true;
}

// A binary STL whose size does not fit its facet count: truncated, or the count is wrong.
[[noreturn]] void binary_size_error(const std::string &bytes, const std::string &path)
{
  const std::string head = "binary STL file '" + path + "' (" + std::to_string(bytes.size()) + " bytes): ";
  if (bytes.size() < 84) throw MeshError(head + "shorter than the 84-byte header with the facet count");
  const std::uint64_t n = facet_count(bytes), want = 84 + 50 * n, have = bytes.size();
  std::string msg = head + "the header gives " + std::to_string(n) + " facets, which take 84 + 50*" + std::to_string(n) + " = " +
                    std::to_string(want) + " bytes; ";
  if (have < want)
    msg += "the file ends inside facet " + std::to_string((have - 84) / 50 + 1) + " (truncated, or a wrong facet count)";
  else
    msg += std::to_string(have - want) + " bytes follow the last facet (a wrong facet count?)";
  if ((have - 84) % 50 == 0) msg += "; the size fits " + std::to_string((have - 84) / 50) + " facets";
  throw MeshError(msg);
}

}  // namespace

bool looks_like_binary_stl(const std::string &bytes)
{
  if (bytes.size() < 84) return false;
  return bytes.size() == 84 + 50 * std::size_t(facet_count(bytes));
}

std::vector<TriangleNodes> read_stl(const std::string &path)
{
  const std::string bytes = slurp(path);
  if (bytes.empty()) throw MeshError("STL file '" + path + "' is empty");
  if (looks_like_binary_stl(bytes)) return parse_binary(bytes, path);
  if (!looks_like_text(bytes)) binary_size_error(bytes, path);
  return parse_ascii(bytes, path);
}

}  // namespace dembridge::mesh
