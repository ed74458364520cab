#include "vertex_loads.h"

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <numeric>
#include <string>

namespace dembridge::mesh {

namespace {
std::string fmt(const Vec3 &p)
{
  char buf[96];
  std::snprintf(buf, sizeof(buf), "(%.9g, %.9g, %.9g)", p[0], p[1], p[2]);
  return buf;
}
}  // namespace

CornerPoints match_corners(const TriangleMesh &m, const std::vector<Vec3> &points, double tol)
{
  // points sorted by x: each corner looks only at those with |x - x_corner| <= tol
  std::vector<int> order(points.size());
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(), [&](int a, int b) { return points[a][0] < points[b][0]; });
  CornerPoints map(m.size());
  for (int t = 0; t < m.size(); ++t)
    for (int k = 0; k < 3; ++k) {
      const Vec3 &c = m.node(t, k);
      auto lo = std::lower_bound(order.begin(), order.end(), c[0] - tol,
                                 [&](int j, double x) { return points[j][0] < x; });
      int found = -1;
      for (auto it = lo; it != order.end() && points[*it][0] <= c[0] + tol; ++it) {
        if (norm(sub(points[*it], c)) > tol) continue;
        if (found >= 0)
          throw MeshError("vertex " + std::to_string(k + 1) + " of triangle " + std::to_string(t + 1) + " at " +
                          fmt(c) + " is within the match tolerance of two mapped points, " +
                          std::to_string(std::min(found, *it) + 1) + " and " + std::to_string(std::max(found, *it) + 1));
        found = *it;
      }
      if (found < 0) {
        int nearest = -1;
        double d = 0;
        for (std::size_t j = 0; j < points.size(); ++j) {
          const double dj = norm(sub(points[j], c));
          if (nearest < 0 || dj < d) nearest = static_cast<int>(j), d = dj;
        }
        char buf[64];
        std::snprintf(buf, sizeof(buf), "%.3g", d);
        throw MeshError("vertex " + std::to_string(k + 1) + " of triangle " + std::to_string(t + 1) + " at " + fmt(c) +
                        " has no mapped point within the match tolerance" +
                        (nearest < 0 ? std::string() : " (the nearest, point " + std::to_string(nearest + 1) +
                                                           ", is " + buf + " away)"));
      }
      map[t][k] = found;
    }
  return map;
}

std::vector<TriangleNodes> nodes_from_points(const CornerPoints &map, const std::vector<Vec3> &points)
{
  std::vector<TriangleNodes> out(map.size());
  for (std::size_t t = 0; t < map.size(); ++t)
    for (int k = 0; k < 3; ++k) out[t][k] = points[map[t][k]];
  return out;
}

Vec3 barycentric(const TriangleMesh &m, int t, const Vec3 &p)
{
  // sub-triangle areas along the normal, divided by the triangle's
  const Vec3 &a = m.node(t, 0), &b = m.node(t, 1), &c = m.node(t, 2);
  const Vec3 n = cross(sub(b, a), sub(c, a));
  const double nn = dot(n, n);
  const double w0 = dot(cross(sub(b, p), sub(c, p)), n) / nn;
  const double w1 = dot(cross(sub(c, p), sub(a, p)), n) / nn;
  return {w0, w1, 1.0 - w0 - w1};
}

namespace {
// Word w of a contact's bytes as the integer whose order is memcmp's on those 8 bytes (byte 0 most
// significant), so the canonical order is the bytewise one of the contacts' values.
static_assert(__BYTE_ORDER__ == __ORDER_LITTLE_ENDIAN__, "memcmp order of a word is its byte-swapped value");
static_assert(sizeof(MeshContact) == 7 * sizeof(std::uint64_t), "a contact is 7 words");
inline std::uint64_t word(const MeshContact &c, int w)
{
  std::uint64_t v;
  std::memcpy(&v, reinterpret_cast<const unsigned char *>(&c) + 8 * w, sizeof v);
  return __builtin_bswap64(v);
}
}  // namespace

void distribute_contacts(const TriangleMesh &m, const CornerPoints &map, const MeshContact *contacts, std::size_t n,
                         double *out)
{
  // the order of memcmp over the contacts, sorted as (first word, index) keys: the first word (the
  // triangle) nearly always decides, the rest only between contacts on one triangle
  std::vector<std::pair<std::uint64_t, std::uint32_t>> order(n);
  for (std::size_t i = 0; i < n; ++i) order[i] = {word(contacts[i], 0), std::uint32_t(i)};
  std::sort(order.begin(), order.end(), [contacts](const auto &a, const auto &b) {
    if (a.first != b.first) return a.first < b.first;
    for (int w = 1; w < 7; ++w) {
      const std::uint64_t x = word(contacts[a.second], w), y = word(contacts[b.second], w);
      if (x != y) return x < y;
    }
    return false;
  });
  for (const auto &o : order) {
    const MeshContact &c = contacts[o.second];
    const int t = static_cast<int>(c.tri);
    const Vec3 w = barycentric(m, t, {c.cp[0], c.cp[1], c.cp[2]});
    for (int a = 0; a < 3; ++a) {
      const double p0 = w[0] * c.f[a], p1 = w[1] * c.f[a];
      out[3 * map[t][0] + a] += p0;
      out[3 * map[t][1] + a] += p1;
      out[3 * map[t][2] + a] += c.f[a] - p0 - p1;
    }
  }
}

}  // namespace dembridge::mesh
