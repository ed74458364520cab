// Mesh output for ParaView: legacy or XML (.vtp) VTK polydata and ASCII STL, several meshes in one file. Used by
// fix mesh/dump and by the dump styles mesh/stl and mesh/vtk (walls/mesh_commands/mesh_output.h).
//
// VTK: one triangle per cell, 3 points per triangle (nodes are not shared, as in LIGGGHTS), then
// the cell and point data chosen by VtkFields. The LIGGGHTS-named fields (dump mesh/vtk keywords)
// carry LIGGGHTS's array names, so ParaView states made for LIGGGHTS output keep working.
#pragma once

#include "triangle_mesh.h"

#include <ostream>
#include <string>
#include <vector>

namespace dembridge::mesh {

struct MeshFrame {
  const TriangleMesh *mesh;
  std::vector<double> tri_force;  // 3 values per triangle (force on it, summed over ranks), or empty
  std::vector<double> wear;       // 1 value per triangle (Finnie wear), or empty (written as 0)
  const char *name;
};

struct VtkFields {
  // fix mesh/dump's set: "mesh" (index of the mesh in the file), "normal", "force", point "velocity"
  bool mesh_index = true, normal = true, force = true, node_velocity = true;
  // dump mesh/vtk keywords (LIGGGHTS 3.8 array names)
  bool stress = false;             // stress: normal_stress_average |f.n|/A, shear_stress_average |f-(f.n)n|/A
  bool stress_components = false;  // stresscomponents: "stress" = f/A
  bool triangle_id = false;        // id: "meshid" = triangle id in its mesh (file order, 0-based)
  bool triangle_index = false;     // index: "index" (the same id: every rank holds the whole mesh)
  bool triangle_velocity = false;  // vel: "v" = mean of the 3 node velocities
  bool area = false;               // area: "area"
  bool active_edges = false;       // aedges: "active_edges" (number of active edges, 0-3)
  bool active_corners = false;     // acorners: "active_corners"
  bool wear = false;               // wear: "wear" (fix mesh/surface/stress ... wear finnie; 0 without)
  static VtkFields none() { return {false, false, false, false}; }
};

// One array of a frame, per triangle of every mesh (cell data) or per node (point data, 3 per triangle).
struct MeshArray {
  const char *legacy;  // its legacy VTK keyword: "SCALARS", "VECTORS" or "NORMALS"
  std::string name;
  bool integer;
  int components;  // 1 or 3
  bool point;      // point data (the node velocities) instead of cell data
  std::vector<double> values;
};
// The arrays VtkFields asks for, in file order (the same for legacy and XML files).
std::vector<MeshArray> mesh_arrays(const std::vector<MeshFrame> &meshes, const VtkFields &fields);

void write_vtk(std::ostream &os, const std::vector<MeshFrame> &meshes, const char *title,
               const VtkFields &fields = VtkFields{});
// VTK XML PolyData (.vtp, ASCII): the same points (Float64), triangles and arrays (Int32 / Float64 %.17g).
void write_vtp(std::ostream &os, const std::vector<MeshFrame> &meshes, const VtkFields &fields = VtkFields{});
void write_stl(std::ostream &os, const std::vector<MeshFrame> &meshes);
// Binary STL (open the stream in binary mode): 80-byte header, triangle count, per triangle the
// normal and the 3 vertices as little-endian 32-bit floats and a zero attribute word; all meshes in
// one solid, as LIGGGHTS's `dump mesh/stl ... binary`. stl_reader.h reads it back.
void write_stl_binary(std::ostream &os, const std::vector<MeshFrame> &meshes);

}  // namespace dembridge::mesh
