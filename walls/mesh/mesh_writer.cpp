#include "mesh_writer.h"

#include <cmath>
#include <cstdint>
#include <cstring>
#include <functional>
#include <iomanip>

namespace dembridge::mesh {

namespace {

// Calls f(frame index, frame, triangle) for every triangle of every mesh, in file order.
void each_triangle(const std::vector<MeshFrame> &meshes, const std::function<void(std::size_t, const MeshFrame &, int)> &f)
{
  for (std::size_t i = 0; i < meshes.size(); ++i)
    for (int t = 0; t < meshes[i].mesh->size(); ++t) f(i, meshes[i], t);
}

Vec3 triangle_force(const MeshFrame &f, int t)
{
  if (f.tri_force.size() != 3 * std::size_t(f.mesh->size())) return {0.0, 0.0, 0.0};
  const double *p = &f.tri_force[3 * std::size_t(t)];
  return {p[0], p[1], p[2]};
}

void put(std::ostream &os, const Vec3 &v) { os << v[0] << ' ' << v[1] << ' ' << v[2] << '\n'; }

// One cell (or point) array in legacy VTK: a scalar of the given type or a 3-vector.
void scalars(std::ostream &os, const std::vector<MeshFrame> &meshes, const char *name, const char *type,
             const std::function<double(std::size_t, const MeshFrame &, int)> &value)
{
  os << "SCALARS " << name << ' ' << type << " 1\nLOOKUP_TABLE default\n";
  each_triangle(meshes, [&](std::size_t i, const MeshFrame &f, int t) { os << value(i, f, t) << '\n'; });
}

void vectors(std::ostream &os, const std::vector<MeshFrame> &meshes, const char *kind, const char *name,
             const std::function<Vec3(const MeshFrame &, int)> &value)
{
  os << kind << ' ' << name << " double\n";
  each_triangle(meshes, [&](std::size_t, const MeshFrame &f, int t) { put(os, value(f, t)); });
}

}  // namespace

void write_vtk(std::ostream &os, const std::vector<MeshFrame> &meshes, const char *title, const VtkFields &want)
{
  int n = 0;
  for (const auto &f : meshes) n += f.mesh->size();
  os << std::setprecision(17);
  os << "# vtk DataFile Version 2.0\n" << title << "\nASCII\nDATASET POLYDATA\n";
  os << "POINTS " << 3 * n << " double\n";
  each_triangle(meshes, [&](std::size_t, const MeshFrame &f, int t) {
    for (int k = 0; k < 3; ++k) put(os, f.mesh->node(t, k));
  });
  os << "POLYGONS " << n << ' ' << 4 * n << '\n';
  for (int t = 0; t < n; ++t) os << "3 " << 3 * t << ' ' << 3 * t + 1 << ' ' << 3 * t + 2 << '\n';

  const bool any_cell = want.mesh_index || want.normal || want.force || want.stress || want.stress_components ||
                        want.triangle_id || want.triangle_index || want.triangle_velocity || want.area ||
                        want.active_edges || want.active_corners || want.wear;
  if (any_cell) os << "CELL_DATA " << n << '\n';
  if (want.mesh_index) scalars(os, meshes, "mesh", "int", [](std::size_t i, const MeshFrame &, int) { return double(i); });
  if (want.normal) vectors(os, meshes, "NORMALS", "normal", [](const MeshFrame &f, int t) { return f.mesh->normal(t); });
  if (want.force) vectors(os, meshes, "VECTORS", "force", triangle_force);
  if (want.stress) {
    // LIGGGHTS fix mesh/surface/stress: both taken positive, the normal's orientation being arbitrary
    scalars(os, meshes, "normal_stress_average", "double", [](std::size_t, const MeshFrame &f, int t) {
      return std::fabs(dot(triangle_force(f, t), f.mesh->normal(t))) / f.mesh->area(t);
    });
    scalars(os, meshes, "shear_stress_average", "double", [](std::size_t, const MeshFrame &f, int t) {
      const Vec3 fo = triangle_force(f, t), nn = f.mesh->normal(t);
      return norm(sub(fo, scale(nn, dot(fo, nn)))) / f.mesh->area(t);
    });
  }
  if (want.stress_components)
    vectors(os, meshes, "VECTORS", "stress",
            [](const MeshFrame &f, int t) { return scale(triangle_force(f, t), 1.0 / f.mesh->area(t)); });
  if (want.triangle_id) scalars(os, meshes, "meshid", "int", [](std::size_t, const MeshFrame &, int t) { return double(t); });
  if (want.triangle_index) scalars(os, meshes, "index", "int", [](std::size_t, const MeshFrame &, int t) { return double(t); });
  if (want.triangle_velocity)
    vectors(os, meshes, "VECTORS", "v", [](const MeshFrame &f, int t) {
      if (!f.mesh->has_velocity()) return Vec3{0.0, 0.0, 0.0};
      return scale(add(add(f.mesh->node_velocity(t, 0), f.mesh->node_velocity(t, 1)), f.mesh->node_velocity(t, 2)), 1.0 / 3.0);
    });
  if (want.wear)
    scalars(os, meshes, "wear", "double", [](std::size_t, const MeshFrame &f, int t) {
      return f.wear.size() == std::size_t(f.mesh->size()) ? f.wear[std::size_t(t)] : 0.0;
    });
  if (want.area) scalars(os, meshes, "area", "double", [](std::size_t, const MeshFrame &f, int t) { return f.mesh->area(t); });
  if (want.active_edges)
    scalars(os, meshes, "active_edges", "int", [](std::size_t, const MeshFrame &f, int t) {
      return double(f.mesh->edge_active(t, 0) + f.mesh->edge_active(t, 1) + f.mesh->edge_active(t, 2));
    });
  if (want.active_corners)
    scalars(os, meshes, "active_corners", "int", [](std::size_t, const MeshFrame &f, int t) {
      return double(f.mesh->corner_active(t, 0) + f.mesh->corner_active(t, 1) + f.mesh->corner_active(t, 2));
    });
  if (want.node_velocity) {
    os << "POINT_DATA " << 3 * n << "\nVECTORS velocity double\n";
    each_triangle(meshes, [&](std::size_t, const MeshFrame &f, int t) {
      for (int k = 0; k < 3; ++k) put(os, f.mesh->has_velocity() ? f.mesh->node_velocity(t, k) : Vec3{0.0, 0.0, 0.0});
    });
  }
}

void write_stl(std::ostream &os, const std::vector<MeshFrame> &meshes)
{
  os << std::setprecision(17);
  for (const auto &f : meshes) {
    os << "solid " << f.name << '\n';
    for (int t = 0; t < f.mesh->size(); ++t) {
      os << "  facet normal ";
      put(os, f.mesh->normal(t));
      os << "    outer loop\n";
      for (int k = 0; k < 3; ++k) {
        os << "      vertex ";
        put(os, f.mesh->node(t, k));
      }
      os << "    endloop\n  endfacet\n";
    }
    os << "endsolid " << f.name << '\n';
  }
}

namespace {

void put_binary(std::ostream &os, const void *p, std::size_t n) { os.write(static_cast<const char *>(p), std::streamsize(n)); }

void put_floats(std::ostream &os, const Vec3 &v)
{
  const float f[3] = {float(v[0]), float(v[1]), float(v[2])};
  put_binary(os, f, sizeof f);
}

}  // namespace

void write_stl_binary(std::ostream &os, const std::vector<MeshFrame> &meshes)
{
  static_assert(sizeof(float) == 4, "STL stores 32-bit floats");
  char header[80];
  std::memset(header, ' ', sizeof header);
  const char title[] = "STL File written by dembridge";
  std::memcpy(header, title, sizeof title - 1);
  put_binary(os, header, sizeof header);
  std::uint32_t n = 0;
  for (const auto &f : meshes) n += std::uint32_t(f.mesh->size());
  put_binary(os, &n, sizeof n);
  const std::uint16_t attribute = 0;
  each_triangle(meshes, [&](std::size_t, const MeshFrame &f, int t) {
    put_floats(os, f.mesh->normal(t));
    for (int k = 0; k < 3; ++k) put_floats(os, f.mesh->node(t, k));
    put_binary(os, &attribute, sizeof attribute);
  });
}

}  // namespace dembridge::mesh
