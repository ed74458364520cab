#include "mesh_writer.h"

#include <iomanip>

namespace dembridge::mesh {

void write_vtk(std::ostream &os, const std::vector<MeshFrame> &meshes, const char *title)
{
  int n = 0;
  for (const auto &f : meshes) n += f.mesh->size();
  os << std::setprecision(17);
  os << "# vtk DataFile Version 2.0\n" << title << "\nASCII\nDATASET POLYDATA\n";
  os << "POINTS " << 3 * n << " double\n";
  for (const auto &f : meshes)
    for (int t = 0; t < f.mesh->size(); ++t)
      for (int k = 0; k < 3; ++k) {
        const Vec3 &p = f.mesh->node(t, k);
        os << p[0] << ' ' << p[1] << ' ' << p[2] << '\n';
      }
  os << "POLYGONS " << n << ' ' << 4 * n << '\n';
  for (int t = 0; t < n; ++t) os << "3 " << 3 * t << ' ' << 3 * t + 1 << ' ' << 3 * t + 2 << '\n';
  os << "CELL_DATA " << n << "\nSCALARS mesh int 1\nLOOKUP_TABLE default\n";
  for (std::size_t i = 0; i < meshes.size(); ++i)
    for (int t = 0; t < meshes[i].mesh->size(); ++t) os << i << '\n';
  os << "NORMALS normal double\n";
  for (const auto &f : meshes)
    for (int t = 0; t < f.mesh->size(); ++t) {
      const Vec3 &v = f.mesh->normal(t);
      os << v[0] << ' ' << v[1] << ' ' << v[2] << '\n';
    }
  os << "VECTORS force double\n";
  for (const auto &f : meshes)
    for (int t = 0; t < f.mesh->size(); ++t) {
      const bool has = f.tri_force.size() == 3 * std::size_t(f.mesh->size());
      for (int k = 0; k < 3; ++k) os << (has ? f.tri_force[3 * std::size_t(t) + k] : 0.0) << (k < 2 ? ' ' : '\n');
    }
  os << "POINT_DATA " << 3 * n << "\nVECTORS velocity double\n";
  for (const auto &f : meshes)
    for (int t = 0; t < f.mesh->size(); ++t)
      for (int k = 0; k < 3; ++k) {
        const Vec3 v = f.mesh->has_velocity() ? f.mesh->node_velocity(t, k) : Vec3{0.0, 0.0, 0.0};
        os << v[0] << ' ' << v[1] << ' ' << v[2] << '\n';
      }
}

void write_stl(std::ostream &os, const std::vector<MeshFrame> &meshes)
{
  os << std::setprecision(17);
  for (const auto &f : meshes) {
    os << "solid " << f.name << '\n';
    for (int t = 0; t < f.mesh->size(); ++t) {
      const Vec3 &nn = f.mesh->normal(t);
      os << "  facet normal " << nn[0] << ' ' << nn[1] << ' ' << nn[2] << "\n    outer loop\n";
      for (int k = 0; k < 3; ++k) {
        const Vec3 &p = f.mesh->node(t, k);
        os << "      vertex " << p[0] << ' ' << p[1] << ' ' << p[2] << '\n';
      }
      os << "    endloop\n  endfacet\n";
    }
    os << "endsolid " << f.name << '\n';
  }
}

}  // namespace dembridge::mesh
