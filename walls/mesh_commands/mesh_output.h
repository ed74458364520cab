// One frame of mesh output, shared by fix mesh/dump and the dump styles mesh/stl and mesh/vtk:
// gathers the meshes (collective: the per-triangle forces are summed over ranks) and writes one
// file on rank 0 with the writers of walls/mesh/mesh_writer.h.
#pragma once

#include "mesh_writer.h"

#include <string>
#include <utility>
#include <vector>

namespace LAMMPS_NS {
class LAMMPS;
}

namespace dembridge {

struct MeshOutput {
  bool vtk = true;                      // false: STL
  bool binary_stl = false;              // STL only: binary instead of ASCII
  mesh::VtkFields fields;               // VTK only
  std::string file;                     // '*' is replaced by the timestep
  std::vector<std::string> mesh_ids;    // fix mesh/surface(/stress) IDs, in file order
  std::string caller;                   // names the command in errors, e.g. "dump mesh/vtk (id d)"
  // frames written so far (file name, time): the .pvd collection of .vtp frames
  std::vector<std::pair<std::string, double>> series;
};

// The IDs of every fix mesh/surface and mesh/surface/stress defined so far, in fix order.
std::vector<std::string> all_mesh_ids(LAMMPS_NS::LAMMPS *lmp);

// Errors (naming out.caller) if a mesh ID is unknown or not a mesh.
void check_mesh_ids(LAMMPS_NS::LAMMPS *lmp, const MeshOutput &out);

// Writes the current state of the meshes to out.file (with '*' replaced by the step): legacy VTK, VTK XML
// for a .vtp name (and the .pvd collection listing every frame with its time), or STL. Collective.
void write_mesh_frame(LAMMPS_NS::LAMMPS *lmp, MeshOutput &out);

}  // namespace dembridge
