#include "dump_custom_vtk.h"
#include "command_args.h"

#include "dump_modify_snapshot.h"
#include "style_registry.h"

#include "atom.h"
#include "comm.h"
#include "compute.h"
#include "domain.h"
#include "error.h"
#include "fix.h"
#include "group.h"
#include "input.h"
#include "modify.h"
#include "output.h"
#include "region.h"
#include "update.h"
#include "variable.h"

#include <mpi.h>

#include <algorithm>
#include <climits>
#include <cmath>
#include <cstdint>
#include <fstream>
#include <map>
#include <numeric>
#include <optional>

using namespace LAMMPS_NS;

namespace dembridge {

namespace {

// Atom quantities; the key is LIGGGHTS's attribute order (its enum), which orders the arrays in the file.
enum Quantity { kId, kType, kMass, kIx, kIy, kIz, kVx, kVy, kVz, kFx, kFy, kFz, kRadius, kDiameter, kOmegax,
                kOmegay, kOmegaz, kTqx, kTqy, kTqz, kDensity };

struct Attribute {
  const char *name;
  int key;
  Quantity q;
  bool integer;
};

constexpr Attribute kAttributes[] = {
    {"id", 3, kId, true},          {"type", 5, kType, true},       {"mass", 7, kMass, false},
    {"ix", 26, kIx, true},         {"iy", 27, kIy, true},          {"iz", 28, kIz, true},
    {"vx", 29, kVx, false},        {"vy", 30, kVy, false},         {"vz", 31, kVz, false},
    {"fx", 32, kFx, false},        {"fy", 33, kFy, false},         {"fz", 34, kFz, false},
    {"radius", 40, kRadius, false}, {"diameter", 41, kDiameter, false}, {"omegax", 42, kOmegax, false},
    {"omegay", 43, kOmegay, false}, {"omegaz", 44, kOmegaz, false}, {"tqx", 48, kTqx, false},
    {"tqy", 49, kTqy, false},      {"tqz", 50, kTqz, false},       {"density", 55, kDensity, false}};

// Attribute keys that start a vector (x, y, z components at key, key+1, key+2): LIGGGHTS writes
// them as one 3-component array named without the trailing 'x' (ix iy iz -> "i").
constexpr int kVectorStarts[] = {26, 29, 32, 42, 48};
constexpr int kFirstCustomKey = 1000;  // c_/f_/v_ come after every atom attribute, in argument order

constexpr const char *kSupported =
    "id type mass x y z ix iy iz vx vy vz fx fy fz radius diameter density omegax omegay omegaz tqx tqy tqz "
    "c_ID c_ID[I] f_ID f_ID[I] v_name";

}  // namespace

DumpCustomVTK::DumpCustomVTK(LAMMPS *lmp, int narg, char **arg) : SelfWritingDump(lmp, narg, arg)
{
  caller_ = std::string("dump custom/vtk (id ") + arg[0] + ")";
  pattern_ = arg[4];
  clearstep = 1;  // computes are invoked
  if (narg == 5) fail("attributes", std::string("none given (expected some of: ") + kSupported + ")");
  if (pattern_.find('%') != std::string::npos)
    fail("file '" + pattern_ + "'", "'%' (a file per rank) is not allowed, as in LIGGGHTS 3.8: use a .pvtp or .pvtu name");
  if (const auto ext = vtkout::unwritten_xml_extension(pattern_))
    fail("file '" + pattern_ + "'", "'" + *ext + "' is not written; expected .vtk (legacy), .vtp, .vtu, .pvtp or .pvtu");
  kind_ = vtkout::file_kind(pattern_);
  if (domain->triclinic) fail("box", "a triclinic box is not supported (its bounding box is a hexahedron)");
  if (!atom->radius_flag || !atom->rmass_flag || !atom->omega_flag) fail("atom style", "needs atom_style sphere (LIGGGHTS's granular)");
  parse_attributes(narg, arg);
  modify_snapshot_ = dump_modify_snapshot(this);
}

void DumpCustomVTK::fail(const std::string &what, const std::string &why) const
{
  error->all(FLERR, caller_ + ": " + what + ": " + why);
}

void DumpCustomVTK::parse_attributes(int narg, char **arg)
{
  std::map<int, Field> scalars;  // by key: a repeated attribute ('type type') is written once
  for (int iarg = 5; iarg < narg; ++iarg) {
    const std::string w = arg[iarg];
    if (w == "x" || w == "y" || w == "z") continue;  // the points
    const Attribute *a = nullptr;
    for (const Attribute &c : kAttributes)
      if (w == c.name) a = &c;
    Field f;
    f.name = f.word = w;
    if (a) {
      f.key = a->key;
      f.integer = a->integer;
      f.what = {a->q};
    } else if (w.size() > 2 && (w.compare(0, 2, "c_") == 0 || w.compare(0, 2, "f_") == 0 || w.compare(0, 2, "v_") == 0)) {
      f.key = kFirstCustomKey + iarg;
      f.source = w[0] == 'c' ? 1 : w[0] == 'f' ? 2 : 3;
      f.id = w.substr(2);
      const auto open = f.id.find('[');
      if (open != std::string::npos) {
        if (f.source == 3) fail("attribute '" + w + "'", "a variable takes no index");
        if (f.id.back() != ']') fail("attribute '" + w + "'", "expected ID[I] with a closing ']'");
        const std::string index = f.id.substr(open + 1, f.id.size() - open - 2);
        const std::optional<long long> column = args::integer(lmp, index);
        if (index.find_first_not_of("0123456789") != std::string::npos || !column || *column > INT_MAX)
          fail("attribute '" + w + "'", "expected a non-negative integer index between [ and ]");
        f.column = int(*column);
        f.id = f.id.substr(0, open);
      }
      if (f.source == 3) f.name = f.id;  // LIGGGHTS names a variable's array without 'v_'
      check_source(f);
    } else {
      fail("attribute '" + w + "'", std::string("unknown or not available for atom_style sphere (expected one of: ") +
                                        kSupported + ")");
    }
    scalars.emplace(f.key, f);
  }
  for (int start : kVectorStarts) {
    if (!(scalars.count(start) && scalars.count(start + 1) && scalars.count(start + 2))) continue;
    Field v = scalars[start];
    v.name = v.name.substr(0, v.name.find('x'));
    v.components = 3;
    v.what = {scalars[start].what[0], scalars[start + 1].what[0], scalars[start + 2].what[0]};
    scalars.erase(start + 1);
    scalars.erase(start + 2);
    scalars[start] = v;
  }
  for (auto &kv : scalars) fields_.push_back(kv.second);
}

void DumpCustomVTK::check_source(const Field &f) const
{
  const std::string what = "attribute '" + f.word + "'";
  if (f.source == 3) {
    const int ivar = input->variable->find(f.id.c_str());
    if (ivar < 0) fail(what, "no variable named '" + f.id + "'");
    if (!input->variable->atomstyle(ivar)) fail(what, "variable '" + f.id + "' is not atom-style");
    return;
  }
  int peratom = 0, cols = 0;
  if (f.source == 1) {
    Compute *c = modify->get_compute_by_id(f.id);
    if (!c) fail(what, "no compute with ID '" + f.id + "'");
    peratom = c->peratom_flag;
    cols = c->size_peratom_cols;
  } else {
    Fix *x = modify->get_fix_by_id(f.id);
    if (!x) fail(what, "no fix with ID '" + f.id + "'");
    peratom = x->peratom_flag;
    cols = x->size_peratom_cols;
  }
  const char *kind = f.source == 1 ? "compute" : "fix";
  if (!peratom) fail(what, std::string(kind) + " '" + f.id + "' has no per-atom values");
  if (f.column == 0 && cols > 0)
    fail(what, std::string(kind) + " '" + f.id + "' has a per-atom array: give a column, e.g. [1]");
  if (f.column > 0 && cols == 0)
    fail(what, std::string(kind) + " '" + f.id + "' has a per-atom vector: give no index (or [0])");
  if (f.column > cols) fail(what, "column " + std::to_string(f.column) + " of " + std::to_string(cols));
}

int DumpCustomVTK::modify_param(int narg, char **arg)
{
  const std::string k = arg[0];
  if (k == "label" || k == "region") {
    if (narg < 2) fail("dump_modify " + k, "expected a value");
    if (k == "label") title_ = arg[1];
    else region_id_ = std::string(arg[1]) == "none" ? "" : arg[1];
    if (!region_id_.empty() && !domain->get_region_by_id(region_id_))
      fail("dump_modify region " + region_id_, "no region with that ID");
    return 2;
  }
  if (k == "binary" && narg >= 2 && std::string(arg[1]) == "no") return 2;
  fail("dump_modify keyword '" + k + "'",
       "not supported; dump custom/vtk takes 'first', 'every', 'every/time', 'label', 'region' and 'binary no'");
}

void DumpCustomVTK::init_style()
{
  if (const char *k = changed_dump_modify_keyword(this, modify_snapshot_))
    fail(std::string("dump_modify keyword '") + k + "'",
         "not supported; dump custom/vtk takes 'first', 'every', 'every/time', 'label', 'region' and 'binary no'");
  computes_.assign(fields_.size(), nullptr);
  fixes_.assign(fields_.size(), nullptr);
  variables_.assign(fields_.size(), -1);
  for (std::size_t k = 0; k < fields_.size(); ++k) {
    const Field &f = fields_[k];
    if (f.source == 0) continue;
    check_source(f);  // the ID may have been redefined since the dump line
    if (f.source == 1) computes_[k] = modify->get_compute_by_id(f.id);
    if (f.source == 2) {
      fixes_[k] = modify->get_fix_by_id(f.id);
      int every = 0;  // this dump's interval as Output holds it (0: a variable)
      for (int d = 0; d < output->ndump; ++d)
        if (output->dump[d] == this) every = output->every_dump[d];
      if (every > 0 && fixes_[k]->peratom_freq > 0 && every % fixes_[k]->peratom_freq)
        fail("attribute '" + f.word + "'", "fix '" + f.id + "' is not computed at the dump's steps");
    }
    if (f.source == 3) variables_[k] = input->variable->find(f.id.c_str());
  }
  if (!region_id_.empty() && !domain->get_region_by_id(region_id_))
    fail("dump_modify region " + region_id_, "no region with that ID");
}

double DumpCustomVTK::atom_value(int q, int i) const
{
  switch (q) {
    case kId: return static_cast<double>(atom->tag[i]);
    case kType: return atom->type[i];
    case kMass: return atom->rmass ? atom->rmass[i] : atom->mass[atom->type[i]];
    case kIx: return static_cast<double>((atom->image[i] & IMGMASK) - IMGMAX);
    case kIy: return static_cast<double>((atom->image[i] >> IMGBITS & IMGMASK) - IMGMAX);
    case kIz: return static_cast<double>((atom->image[i] >> IMG2BITS) - IMGMAX);
    case kVx: case kVy: case kVz: return atom->v[i][q - kVx];
    case kFx: case kFy: case kFz: return atom->f[i][q - kFx];
    case kRadius: return atom->radius[i];
    case kDiameter: return 2.0 * atom->radius[i];
    case kOmegax: case kOmegay: case kOmegaz: return atom->omega[i][q - kOmegax];
    case kTqx: case kTqy: case kTqz: return atom->torque[i][q - kTqx];
    case kDensity: {
      const double r = atom->radius[i];
      return atom->rmass[i] / (4.0 * M_PI / 3.0 * r * r * r);
    }
  }
  return 0.0;
}

// Each row: the atom ID, x y z, then every field's components.
void DumpCustomVTK::pack_rows(std::vector<double> &rows, int &width)
{
  const int nlocal = atom->nlocal;
  width = 4;
  for (const Field &f : fields_) width += f.components;
  std::vector<char> chosen(nlocal, 0);
  Region *region = region_id_.empty() ? nullptr : domain->get_region_by_id(region_id_);
  if (region) region->prematch();
  for (int i = 0; i < nlocal; ++i)
    chosen[i] = (atom->mask[i] & groupbit) && (!region || region->match(atom->x[i][0], atom->x[i][1], atom->x[i][2]));

  std::vector<std::vector<double>> var_values(fields_.size());
  for (std::size_t k = 0; k < fields_.size(); ++k) {
    if (computes_[k] && !(computes_[k]->invoked_flag & Compute::INVOKED_PERATOM)) {
      computes_[k]->compute_peratom();
      computes_[k]->invoked_flag |= Compute::INVOKED_PERATOM;
    }
    if (variables_[k] >= 0) {
      var_values[k].assign(std::max(nlocal, 1), 0.0);
      input->variable->compute_atom(variables_[k], igroup, var_values[k].data(), 1, 0);
    }
  }
  rows.clear();
  for (int i = 0; i < nlocal; ++i) {
    if (!chosen[i]) continue;
    rows.push_back(static_cast<double>(atom->tag[i]));
    for (int d = 0; d < 3; ++d) rows.push_back(atom->x[i][d]);
    for (std::size_t k = 0; k < fields_.size(); ++k) {
      const Field &f = fields_[k];
      if (f.source == 0) {
        for (int q : f.what) rows.push_back(atom_value(q, i));
        continue;
      }
      double value = 0.0;
      if (computes_[k]) value = f.column ? computes_[k]->array_atom[i][f.column - 1] : computes_[k]->vector_atom[i];
      else if (fixes_[k]) value = f.column ? fixes_[k]->array_atom[i][f.column - 1] : fixes_[k]->vector_atom[i];
      else value = var_values[k][i];
      rows.push_back(value);
    }
  }
}

void DumpCustomVTK::write()
{
  std::vector<double> rows;
  int width = 0;
  pack_rows(rows, width);
  // Gather every rank's rows on rank 0 (counts in doubles).
  const int mine = static_cast<int>(rows.size());
  std::vector<int> counts(comm->nprocs), displs(comm->nprocs, 0);
  MPI_Gather(&mine, 1, MPI_INT, counts.data(), 1, MPI_INT, 0, world);
  long long total = 0;
  if (comm->me == 0) {
    for (int p = 0; p < comm->nprocs; ++p) {
      displs[p] = static_cast<int>(total);
      total += counts[p];
    }
    if (total > INT32_MAX) error->one(FLERR, caller_ + ": too many atoms for one frame");
  }
  std::vector<double> all(comm->me == 0 ? std::max<long long>(total, 1) : 1);
  MPI_Gatherv(rows.data(), mine, MPI_DOUBLE, all.data(), counts.data(), displs.data(), MPI_DOUBLE, 0, world);
  if (comm->me == 0) {
    all.resize(total);
    write_files(all, width, total / width);
  }
}

void DumpCustomVTK::write_files(std::vector<double> &rows, int width, long long nrows)
{
  std::vector<long long> order(nrows);
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(), [&](long long a, long long b) { return rows[a * width] < rows[b * width]; });
  vtkout::ParticleFrame frame;
  frame.xyz.reserve(3 * nrows);
  for (long long r : order)
    for (int d = 0; d < 3; ++d) frame.xyz.push_back(rows[r * width + 1 + d]);
  int col = 4;
  for (const Field &f : fields_) {
    vtkout::ParticleArray a;
    a.name = f.name;
    a.components = f.components;
    a.integer = f.integer;
    a.values.reserve(f.components * nrows);
    for (long long r : order)
      for (int c = 0; c < f.components; ++c) a.values.push_back(rows[r * width + col + c]);
    col += f.components;
    frame.arrays.push_back(std::move(a));
  }
  const long long step = update->ntimestep;
  const std::string file = vtkout::frame_file(pattern_, step);
  if (kind_ == vtkout::FileKind::Legacy) {
    std::ofstream os = open(file);
    vtkout::write_polydata(os, frame, title_);
    std::ofstream box = open(vtkout::bounding_box_file(pattern_, step));
    vtkout::write_bounding_box(box, domain->boxlo, domain->boxhi, title_);
  } else {
    write_xml_frame(frame, file, step);
  }
  const double time = update->atime + static_cast<double>(step - update->atimestep) * update->dt;
  const std::string name = vtkout::base_name(file);
  if (!series_.empty() && series_.back().first == name) series_.back().second = time;  // no '*': one file
  else series_.emplace_back(name, time);
  if (kind_ == vtkout::FileKind::Legacy) {
    std::ofstream os = open(vtkout::series_file(pattern_));
    vtkout::write_series(os, series_);
  } else {
    std::ofstream os = open(vtkxml::pvd_file(pattern_));
    vtkxml::write_pvd(os, series_);
  }
}

// A parallel name (.pvtp, .pvtu) gets its header and one piece holding every particle (rank 0 gathered
// them), named as LIGGGHTS 3.8 names rank 0's piece; the bounding box likewise (.pvtr and its .vtr piece).
void DumpCustomVTK::write_xml_frame(const vtkout::ParticleFrame &frame, const std::string &file, long long step)
{
  const bool unstructured = vtkout::is_unstructured(kind_);
  const std::string box = vtkout::xml_bounding_box_file(pattern_, step);
  if (!vtkout::is_parallel(kind_)) {
    std::ofstream os = open(file);
    vtkout::write_xml_particles(os, frame, unstructured);
    std::ofstream bs = open(box);
    vtkout::write_xml_bounding_box(bs, domain->boxlo, domain->boxhi);
    return;
  }
  const std::string piece = vtkout::piece_file(file), box_piece = vtkout::piece_file(box);
  {
    std::ofstream os = open(piece);
    vtkout::write_xml_particles(os, frame, unstructured);
  }
  std::ofstream os = open(file);
  vtkout::write_xml_parallel_particles(os, frame, unstructured, vtkout::base_name(piece));
  {
    std::ofstream bs = open(box_piece);
    vtkout::write_xml_bounding_box(bs, domain->boxlo, domain->boxhi);
  }
  std::ofstream bs = open(box);
  vtkout::write_xml_parallel_bounding_box(bs, vtkout::base_name(box_piece));
}

std::ofstream DumpCustomVTK::open(const std::string &name) const
{
  std::ofstream os(name);
  if (!os) error->one(FLERR, caller_ + ": cannot open file '" + name + "' for writing");
  return os;
}

static RegisterStyle reg_dump_custom_vtk("dump", "custom/vtk", "LIGGGHTS dump custom/vtk (legacy or XML VTK per frame)",
                                         create_fix<DumpCustomVTK>);

}  // namespace dembridge
