#include "mesh_writer.h"
#include "vtk_xml.h"

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

// Appends an array of one value (or 3-vector) per triangle of every mesh, in file order.
void cell_scalar(std::vector<MeshArray> &out, const std::vector<MeshFrame> &meshes, const char *name, bool integer,
                 const std::function<double(std::size_t, const MeshFrame &, int)> &value)
{
  MeshArray a{"SCALARS", name, integer, 1, false, {}};
  each_triangle(meshes, [&](std::size_t i, const MeshFrame &f, int t) { a.values.push_back(value(i, f, t)); });
  out.push_back(std::move(a));
}

void cell_vector(std::vector<MeshArray> &out, const std::vector<MeshFrame> &meshes, const char *legacy, const char *name,
                 const std::function<Vec3(const MeshFrame &, int)> &value)
{
  MeshArray a{legacy, name, false, 3, false, {}};
  each_triangle(meshes, [&](std::size_t, const MeshFrame &f, int t) {
    const Vec3 v = value(f, t);
    a.values.insert(a.values.end(), {v[0], v[1], v[2]});
  });
  out.push_back(std::move(a));
}

int triangle_count(const std::vector<MeshFrame> &meshes)
{
  int n = 0;
  for (const auto &f : meshes) n += f.mesh->size();
  return n;
}

}  // namespace

std::vector<MeshArray> mesh_arrays(const std::vector<MeshFrame> &meshes, const VtkFields &want)
{
  std::vector<MeshArray> out;
  if (want.mesh_index) cell_scalar(out, meshes, "mesh", true, [](std::size_t i, const MeshFrame &, int) { return double(i); });
  if (want.normal) cell_vector(out, meshes, "NORMALS", "normal", [](const MeshFrame &f, int t) { return f.mesh->normal(t); });
  if (want.force) cell_vector(out, meshes, "VECTORS", "force", triangle_force);
  if (want.stress) {
    // LIGGGHTS fix mesh/surface/stress: both taken positive, the normal's orientation being arbitrary
    cell_scalar(out, meshes, "normal_stress_average", false, [](std::size_t, const MeshFrame &f, int t) {
      return std::fabs(dot(triangle_force(f, t), f.mesh->normal(t))) / f.mesh->area(t);
    });
    cell_scalar(out, meshes, "shear_stress_average", false, [](std::size_t, const MeshFrame &f, int t) {
      const Vec3 fo = triangle_force(f, t), nn = f.mesh->normal(t);
      return norm(sub(fo, scale(nn, dot(fo, nn)))) / f.mesh->area(t);
    });
  }
  if (want.stress_components)
    cell_vector(out, meshes, "VECTORS", "stress",
                [](const MeshFrame &f, int t) { return scale(triangle_force(f, t), 1.0 / f.mesh->area(t)); });
  if (want.triangle_id) cell_scalar(out, meshes, "meshid", true, [](std::size_t, const MeshFrame &, int t) { return double(t); });
  if (want.triangle_index) cell_scalar(out, meshes, "index", true, [](std::size_t, const MeshFrame &, int t) { return double(t); });
  if (want.triangle_velocity)
    cell_vector(out, meshes, "VECTORS", "v", [](const MeshFrame &f, int t) {
      if (!f.mesh->has_velocity()) return Vec3{0.0, 0.0, 0.0};
      return scale(add(add(f.mesh->node_velocity(t, 0), f.mesh->node_velocity(t, 1)), f.mesh->node_velocity(t, 2)), 1.0 / 3.0);
    });
  if (want.wear)
    cell_scalar(out, meshes, "wear", false, [](std::size_t, const MeshFrame &f, int t) {
      return f.wear.size() == std::size_t(f.mesh->size()) ? f.wear[std::size_t(t)] : 0.0;
    });
  if (want.area) cell_scalar(out, meshes, "area", false, [](std::size_t, const MeshFrame &f, int t) { return f.mesh->area(t); });
  if (want.active_edges)
    cell_scalar(out, meshes, "active_edges", true, [](std::size_t, const MeshFrame &f, int t) {
      return double(f.mesh->edge_active(t, 0) + f.mesh->edge_active(t, 1) + f.mesh->edge_active(t, 2));
    });
  if (want.active_corners)
    cell_scalar(out, meshes, "active_corners", true, [](std::size_t, const MeshFrame &f, int t) {
      return double(f.mesh->corner_active(t, 0) + f.mesh->corner_active(t, 1) + f.mesh->corner_active(t, 2));
    });
  if (want.node_velocity) {
    MeshArray a{"VECTORS", "velocity", false, 3, true, {}};
    each_triangle(meshes, [&](std::size_t, const MeshFrame &f, int t) {
      for (int k = 0; k < 3; ++k) {
        const Vec3 v = f.mesh->has_velocity() ? f.mesh->node_velocity(t, k) : Vec3{0.0, 0.0, 0.0};
        a.values.insert(a.values.end(), {v[0], v[1], v[2]});
      }
    });
    out.push_back(std::move(a));
  }
  return out;
}

void write_vtk(std::ostream &os, const std::vector<MeshFrame> &meshes, const char *title, const VtkFields &want)
{
  const int n = triangle_count(meshes);
  os << std::setprecision(17);
  os << "# vtk DataFile Version 2.0\n" << title << "\nASCII\nDATASET POLYDATA\n";
  os << "POINTS " << 3 * n << " double\n";
  each_triangle(meshes, [&](std::size_t, const MeshFrame &f, int t) {
    for (int k = 0; k < 3; ++k) put(os, f.mesh->node(t, k));
  });
  os << "POLYGONS " << n << ' ' << 4 * n << '\n';
  for (int t = 0; t < n; ++t) os << "3 " << 3 * t << ' ' << 3 * t + 1 << ' ' << 3 * t + 2 << '\n';
  const std::vector<MeshArray> arrays = mesh_arrays(meshes, want);
  bool cells = false, points = false;
  for (const MeshArray &a : arrays) {
    if (!a.point && !cells) os << "CELL_DATA " << n << '\n';
    if (a.point && !points) os << "POINT_DATA " << 3 * n << '\n';
    (a.point ? points : cells) = true;
    if (a.components == 1) {
      os << "SCALARS " << a.name << ' ' << (a.integer ? "int" : "double") << " 1\nLOOKUP_TABLE default\n";
      for (double v : a.values) os << v << '\n';
    } else {
      os << a.legacy << ' ' << a.name << " double\n";
      for (std::size_t k = 0; k < a.values.size(); k += 3) put(os, {a.values[k], a.values[k + 1], a.values[k + 2]});
    }
  }
}

// VTK XML PolyData: 3 points per triangle (Float64), one polygon each, the arrays of write_vtk.
void write_vtp(std::ostream &os, const std::vector<MeshFrame> &meshes, const VtkFields &want)
{
  const int n = triangle_count(meshes);
  const std::vector<MeshArray> arrays = mesh_arrays(meshes, want);
  vtkxml::header(os, "PolyData");
  os << "  <PolyData>\n    <Piece NumberOfPoints=\"" << 3 * n
     << "\" NumberOfVerts=\"0\" NumberOfLines=\"0\" NumberOfStrips=\"0\" NumberOfPolys=\"" << n << "\">\n";
  for (bool point : {true, false}) {
    os << (point ? "      <PointData>\n" : "      <CellData>\n");
    for (const MeshArray &a : arrays)
      if (a.point == point) vtkxml::data_array(os, a.integer ? "Int32" : "Float64", a.name, a.components, a.values);
    os << (point ? "      </PointData>\n" : "      </CellData>\n");
  }
  std::vector<double> xyz;
  each_triangle(meshes, [&](std::size_t, const MeshFrame &f, int t) {
    for (int k = 0; k < 3; ++k) {
      const Vec3 p = f.mesh->node(t, k);
      xyz.insert(xyz.end(), {p[0], p[1], p[2]});
    }
  });
  os << "      <Points>\n";
  vtkxml::data_array(os, "Float64", "Points", 3, xyz);
  os << "      </Points>\n      <Polys>\n";
  vtkxml::counting_array(os, "Int64", "connectivity", std::size_t(3 * n), 0, 1);
  vtkxml::counting_array(os, "Int64", "offsets", std::size_t(n), 3, 3);
  os << "      </Polys>\n    </Piece>\n  </PolyData>\n</VTKFile>\n";
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
