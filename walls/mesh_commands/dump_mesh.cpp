#include "dump_mesh.h"

#include "dump_modify_snapshot.h"
#include "mesh_args.h"
#include "style_registry.h"

#include "comm.h"
#include "error.h"
#include "modify.h"

#include <cstring>
#include <string>

using namespace LAMMPS_NS;

namespace dembridge {

namespace {

const char *const vtk_keywords = "stress, stresscomponents, id, index, vel, wear, area, aedges, acorners";

// LIGGGHTS 3.8 keywords for quantities our meshes do not have.
const char *unsupported_vtk_keyword(const std::string &w)
{
  if (w == "temp") return "meshes carry no temperature (no heat transfer)";
  if (w == "liquid") return "meshes carry no liquid content";
  if (w == "owner") return "every rank holds the whole mesh, so a triangle has no owner rank";
  if (w == "nneighs") return "the neighbour count of LIGGGHTS's parallel mesh is not kept";
  if (w == "distaa") return "the minimum active edge distance is not kept";
  return nullptr;
}

}  // namespace

DumpMesh::DumpMesh(LAMMPS *lmp, int narg, char **arg) : SelfWritingDump(lmp, narg, arg)
{
  out_.vtk = std::strcmp(arg[2], "mesh/stl") != 0 && std::strcmp(arg[2], "stl") != 0;  // mesh/gran/VTK = mesh/vtk
  out_.caller = std::string("dump ") + arg[2] + " (id " + arg[0] + ")";
  out_.fields = mesh::VtkFields::none();
  out_.file = arg[4];
  MeshArgs a(lmp, out_.caller, narg, arg, 5);
  check_file_name(a);
  while (!a.done()) {
    const std::string w = a.word("keyword or mesh ID");
    if (out_.vtk ? vtk_keyword(a, w) : stl_keyword(a, w)) continue;
    Fix *f = modify->get_fix_by_id(w);
    if (!f)
      a.fail("'" + w + "'", std::string("neither a keyword (") + (out_.vtk ? vtk_keywords : "local, all, binary") +
                                ") nor the ID of a fix mesh/surface");
    out_.mesh_ids.push_back(w);
    check_mesh_ids(lmp, out_);  // a fix, but is it a mesh?
  }
  if (out_.vtk) {
    const mesh::VtkFields &q = out_.fields;
    if (!(q.stress || q.stress_components || q.triangle_id || q.triangle_index || q.triangle_velocity || q.area || q.wear ||
          q.active_edges || q.active_corners))
      a.fail("quantities", std::string("no dump quantity selected (expected at least one of ") + vtk_keywords + ")");
  }
  if (out_.mesh_ids.empty()) {
    out_.mesh_ids = all_mesh_ids(lmp);
    if (out_.mesh_ids.empty() && comm->me == 0)
      error->warning(FLERR, out_.caller + ": no fix mesh/surface defined yet, so the files will hold no triangles");
  }
  modify_fields_at_creation_ = dump_modify_snapshot(this);
}

// write() is ours, so the Dump base's file handling, formats, sorting, delay, skip ... never run: a
// dump_modify keyword other than those Output reads would be accepted and do nothing.
void DumpMesh::unsupported_modify_keyword(const std::string &keyword)
{
  error->all(FLERR, out_.caller + ": dump_modify keyword '" + keyword +
                        "' is not supported; the mesh dumps take only 'first', 'every' and 'every/time'");
}

int DumpMesh::modify_param(int, char **arg) { unsupported_modify_keyword(arg[0]); }

void DumpMesh::check_file_name(MeshArgs &a) const
{
  const std::string &f = out_.file;
  if (f.find('%') != std::string::npos) a.fail("file '" + f + "'", "one file for all ranks: '%' is not allowed");
  if (!out_.vtk && f.find('*') == std::string::npos)
    a.fail("file '" + f + "'", "expected a name with '*' (one STL file per frame, e.g. post/mesh*.stl), as LIGGGHTS");
  auto ends_with = [&](const char *s) { return f.size() >= std::strlen(s) && f.compare(f.size() - std::strlen(s), std::string::npos, s) == 0; };
  if (out_.vtk && ends_with(".pvtp"))
    a.fail("file '" + f + "'", "'.pvtp' (a file per rank) is not written; use a .vtp (VTK XML) or .vtk (legacy) name");
}

bool DumpMesh::stl_keyword(MeshArgs &a, const std::string &w)
{
  if (w == "local" || w == "all") return true;  // every rank holds the whole mesh: all = local
  if (w == "ghost") a.fail("keyword 'ghost'", "meshes have no ghost triangles here (every rank holds the whole mesh)");
  if (w != "binary") return false;
  out_.binary_stl = true;
  return true;
}

bool DumpMesh::vtk_keyword(MeshArgs &a, const std::string &w)
{
  mesh::VtkFields &q = out_.fields;
  if (w == "stress") q.stress = true;
  else if (w == "stresscomponents") q.stress_components = true;
  else if (w == "id") q.triangle_id = true;
  else if (w == "index") q.triangle_index = true;
  else if (w == "vel") q.triangle_velocity = true;
  else if (w == "area") q.area = true;
  else if (w == "wear") q.wear = true;
  else if (w == "aedges") q.active_edges = true;
  else if (w == "acorners") q.active_corners = true;
  else if (w == "output") {
    const std::string mode = a.word("'output' mode");
    if (mode != "face")
      a.fail("'output " + mode + "'", "only 'output face' (cell data per triangle) is written");
  } else if (const char *why = unsupported_vtk_keyword(w))
    a.fail("keyword '" + w + "'", std::string("not supported: ") + why);
  else return false;
  return true;
}

void DumpMesh::init_style()
{
  if (const char *k = changed_dump_modify_keyword(this, modify_fields_at_creation_)) unsupported_modify_keyword(k);
  check_mesh_ids(lmp, out_);
}

void DumpMesh::write() { write_mesh_frame(lmp, out_); }

static RegisterStyle reg_dump_mesh_stl("dump", "mesh/stl", "LIGGGHTS dump mesh/stl (ASCII STL per frame)", create_fix<DumpMesh>);
static RegisterStyle reg_dump_mesh_vtk("dump", "mesh/vtk", "LIGGGHTS dump mesh/vtk (legacy or XML VTK per frame)", create_fix<DumpMesh>);
// LIGGGHTS 3.8's other names of the same two dumps.
static RegisterStyle reg_dump_mesh_gran_vtk("dump", "mesh/gran/VTK", "LIGGGHTS dump mesh/gran/VTK (= mesh/vtk)", create_fix<DumpMesh>);
static RegisterStyle reg_dump_stl("dump", "stl", "LIGGGHTS dump stl (= mesh/stl)", create_fix<DumpMesh>);

}  // namespace dembridge
