#include "mesh_output.h"
#include "rank_error.h"
#include "vtk_xml.h"

#include "fix_mesh_surface.h"

#include "comm.h"
#include "error.h"
#include "lammps.h"
#include "modify.h"
#include "update.h"

#include <fstream>

using namespace LAMMPS_NS;

namespace dembridge {

std::vector<std::string> all_mesh_ids(LAMMPS *lmp)
{
  std::vector<std::string> ids;
  for (Fix *f : lmp->modify->get_fix_list())
    if (dynamic_cast<FixMeshSurface *>(f)) ids.emplace_back(f->id);
  return ids;
}

void check_mesh_ids(LAMMPS *lmp, const MeshOutput &out)
{
  for (const auto &m : out.mesh_ids) FixMeshSurface::find(lmp, m, out.caller)->keep_whole();  // the writer needs every triangle
}

void write_mesh_frame(LAMMPS *lmp, MeshOutput &out)
{
  const mesh::VtkFields &w = out.fields;
  const bool forces = out.vtk && (w.force || w.stress || w.stress_components);
  std::vector<mesh::MeshFrame> frames;
  for (const auto &mid : out.mesh_ids) {
    FixMeshSurface *m = FixMeshSurface::find(lmp, mid, out.caller);
    frames.push_back({&m->mesh(), forces ? m->triangle_forces_all() : std::vector<double>{},
                      out.vtk && w.wear ? m->wear() : std::vector<double>{}, mid.c_str()});
  }
  if (lmp->comm->me != 0) return;
  std::string name = out.file;
  if (const auto star = name.find('*'); star != std::string::npos)
    name.replace(star, 1, std::to_string(lmp->update->ntimestep));
  std::ofstream os(name, std::ios::out | std::ios::binary);
  if (!os) fail_on_this_rank(lmp, FLERR, out.caller + ": cannot open '" + name + "' for writing");
  const bool xml = out.vtk && vtkxml::extension(out.file) == ".vtp";
  if (xml) mesh::write_vtp(os, frames, w);
  else if (out.vtk) mesh::write_vtk(os, frames, "dembridge mesh", w);
  else if (out.binary_stl) mesh::write_stl_binary(os, frames);
  else mesh::write_stl(os, frames);
  if (!os) fail_on_this_rank(lmp, FLERR, out.caller + ": error writing '" + name + "'");
  if (!xml) return;
  const Update *u = lmp->update;
  const double time = u->atime + static_cast<double>(u->ntimestep - u->atimestep) * u->dt;
  const std::string base = name.substr(name.rfind('/') == std::string::npos ? 0 : name.rfind('/') + 1);
  if (!out.series.empty() && out.series.back().first == base) out.series.back().second = time;  // no '*': one file
  else out.series.emplace_back(base, time);
  const std::string pvd = vtkxml::pvd_file(out.file);
  std::ofstream ps(pvd);
  if (ps) vtkxml::write_pvd(ps, out.series);
  if (!ps) fail_on_this_rank(lmp, FLERR, out.caller + ": cannot write '" + pvd + "'");
}

}  // namespace dembridge
