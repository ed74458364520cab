#include "node_index.h"

#include <cmath>
#include <cstdint>
#include <unordered_map>

namespace dembridge::mesh {

namespace {

struct CellKey {
  std::int64_t i, j, k;
  bool operator==(const CellKey &o) const { return i == o.i && j == o.j && k == o.k; }
};
struct CellHash {
  std::size_t operator()(const CellKey &c) const
  {
    // unsigned products: the same bits as the wrapped signed ones, without the overflow
    return (std::size_t(c.i) * 73856093u) ^ (std::size_t(c.j) * 19349663u) ^ (std::size_t(c.k) * 83492791u);
  }
};

// LIGGGHTS's per-component node comparison: equal, or absolutely closer than the precision.
bool same_coordinate(double a, double b, double precision) { return a == b || std::fabs(a - b) < precision; }

}  // namespace

std::vector<std::array<int, 3>> index_nodes(const std::vector<TriangleNodes> &tris, double precision)
{
  const double cell = 2.0 * precision;
  std::unordered_map<CellKey, std::vector<int>, CellHash> grid;
  std::vector<Vec3> unique;
  std::vector<std::array<int, 3>> ids(tris.size());
  // Cells are only a lookup aid: coordinates beyond +-2^62 cells (1e300 in a bad file, refused later by the
  // mesh checks) share the outermost cell instead of overflowing the integer key.
  auto cell_of = [cell](double x) {
    const double c = std::floor(x / cell), lim = 4611686018427387904.0;
    return std::int64_t(c > lim ? lim : (c < -lim ? -lim : c));
  };
  for (std::size_t t = 0; t < tris.size(); ++t)
    for (int k = 0; k < 3; ++k) {
      const Vec3 &p = tris[t][k];
      const CellKey c{cell_of(p[0]), cell_of(p[1]), cell_of(p[2])};
      int found = -1;
      for (int a = -1; a <= 1 && found < 0; ++a)
        for (int b = -1; b <= 1 && found < 0; ++b)
          for (int d = -1; d <= 1 && found < 0; ++d) {
            auto it = grid.find({c.i + a, c.j + b, c.k + d});
            if (it == grid.end()) continue;
            for (int id : it->second) {
              const Vec3 &q = unique[id];
              if (same_coordinate(p[0], q[0], precision) && same_coordinate(p[1], q[1], precision) &&
                  same_coordinate(p[2], q[2], precision)) {
                found = id;
                break;
              }
            }
          }
      if (found < 0) {
        found = static_cast<int>(unique.size());
        unique.push_back(p);
        grid[c].push_back(found);
      }
      ids[t][k] = found;
    }
  return ids;
}

}  // namespace dembridge::mesh
