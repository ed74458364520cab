#include "mesh_writer.h"

#include <iomanip>

namespace dembridge::mesh {

void write_vtk(std::ostream &os, const TriangleMesh &m, const std::vector<double> &tri_force, const char *title)
{
  const int n = m.size();
  os << std::setprecision(17);
  os << "# vtk DataFile Version 2.0\n" << title << "\nASCII\nDATASET POLYDATA\n";
  os << "POINTS " << 3 * n << " double\n";
  for (int t = 0; t < n; ++t)
    for (int k = 0; k < 3; ++k) os << m.node(t, k)[0] << ' ' << m.node(t, k)[1] << ' ' << m.node(t, k)[2] << '\n';
  os << "POLYGONS " << n << ' ' << 4 * n << '\n';
  for (int t = 0; t < n; ++t) os << "3 " << 3 * t << ' ' << 3 * t + 1 << ' ' << 3 * t + 2 << '\n';
  os << "CELL_DATA " << n << "\nNORMALS normal double\n";
  for (int t = 0; t < n; ++t) os << m.normal(t)[0] << ' ' << m.normal(t)[1] << ' ' << m.normal(t)[2] << '\n';
  if (static_cast<int>(tri_force.size()) == 3 * n) {
    os << "VECTORS force double\n";
    for (int t = 0; t < n; ++t) os << tri_force[3 * t] << ' ' << tri_force[3 * t + 1] << ' ' << tri_force[3 * t + 2] << '\n';
  }
  os << "POINT_DATA " << 3 * n << "\nVECTORS velocity double\n";
  for (int t = 0; t < n; ++t)
    for (int k = 0; k < 3; ++k) {
      const Vec3 v = m.has_velocity() ? m.node_velocity(t, k) : Vec3{0.0, 0.0, 0.0};
      os << v[0] << ' ' << v[1] << ' ' << v[2] << '\n';
    }
}

void write_stl(std::ostream &os, const TriangleMesh &m, const char *solid_name)
{
  os << std::setprecision(17) << "solid " << solid_name << '\n';
  for (int t = 0; t < m.size(); ++t) {
    const Vec3 &nn = m.normal(t);
    os << "  facet normal " << nn[0] << ' ' << nn[1] << ' ' << nn[2] << "\n    outer loop\n";
    for (int k = 0; k < 3; ++k) os << "      vertex " << m.node(t, k)[0] << ' ' << m.node(t, k)[1] << ' ' << m.node(t, k)[2] << '\n';
    os << "    endloop\n  endfacet\n";
  }
  os << "endsolid " << solid_name << '\n';
}

}  // namespace dembridge::mesh
