#include "fix_property_atom_liggghts.h"

#include "mesh_args.h"

#include "atom.h"
#include "comm.h"
#include "error.h"
#include "memory.h"
#include "modify.h"
#include "style_registry.h"
#include "utils.h"

#include <cstring>

using namespace LAMMPS_NS;

namespace dembridge {

bool FixPropertyAtomLiggghts::is_liggghts_syntax(int narg, char **arg)
{
  return narg > 4 && (std::strcmp(arg[4], "scalar") == 0 || std::strcmp(arg[4], "vector") == 0);
}

FixPropertyAtomLiggghts::FixPropertyAtomLiggghts(LAMMPS *lmp, int narg, char **arg) : Fix(lmp, narg, arg)
{
  const std::string cmd = std::string("fix ") + id + " property/atom";
  MeshArgs a(lmp, cmd, narg, arg, 3);
  name_ = a.word("NAME");
  scalar_ = a.word("style") == "scalar";
  const bool restart = a.yes_no("restart");
  ghost_ = a.yes_no("commghost");
  a.yes_no("commrev");  // reverse communication is asked for by the fix that needs it
  while (!a.done()) defaults_.push_back(a.number("default value"));
  if (defaults_.empty()) a.fail("default value", "missing (expected one value for scalar, one per column for vector)");
  if (scalar_ && defaults_.size() != 1)
    a.fail("default value", "a scalar property takes one default value, got " + std::to_string(defaults_.size()));
  if (name_.rfind("i_", 0) == 0 || name_.rfind("d_", 0) == 0 || name_.rfind("i2_", 0) == 0 || name_.rfind("d2_", 0) == 0)
    error->all(FLERR, cmd + ": NAME '" + name_ + "': a LIGGGHTS property name has no i_/d_ prefix (write " +
                          name_.substr(name_.find('_') + 1) + ")");
  int flag = 0, cols = 0;
  if (atom->find_custom(name_.c_str(), flag, cols) >= 0)
    error->all(FLERR, cmd + ": NAME '" + name_ + "': a per-atom property of that name exists already");

  index_ = atom->add_custom(name_.c_str(), 1, scalar_ ? 0 : ncols(), ghost_ ? 1 : 0);
  peratom_flag = 1;
  size_peratom_cols = scalar_ ? 0 : ncols();
  peratom_freq = 1;
  create_attribute = 1;
  restart_peratom = restart ? 1 : 0;
  comm_border = ghost_ ? ncols() : 0;
  comm_forward = ncols();
  comm_reverse = ncols();
  grow_arrays(atom->nmax);
  atom->add_callback(Atom::GROW);
  if (restart) atom->add_callback(Atom::RESTART);
  if (ghost_) atom->add_callback(Atom::BORDER);
  for (int i = 0; i < atom->nlocal; ++i) set_arrays(i);
}

FixPropertyAtomLiggghts::~FixPropertyAtomLiggghts()
{
  atom->delete_callback(id, Atom::GROW);
  if (restart_peratom) atom->delete_callback(id, Atom::RESTART);
  if (ghost_) atom->delete_callback(id, Atom::BORDER);
  if (index_ >= 0) atom->remove_custom(index_, 1, scalar_ ? 0 : ncols());
}

double *FixPropertyAtomLiggghts::values() { return atom->dvector[index_]; }
double **FixPropertyAtomLiggghts::rows() { return atom->darray[index_]; }

double FixPropertyAtomLiggghts::get(int i, int c) { return scalar_ ? atom->dvector[index_][i] : atom->darray[index_][i][c]; }

void FixPropertyAtomLiggghts::put(int i, int c, double v)
{
  if (scalar_) atom->dvector[index_][i] = v;
  else atom->darray[index_][i][c] = v;
}

void FixPropertyAtomLiggghts::refresh_output()
{
  if (scalar_) vector_atom = atom->dvector[index_];
  else array_atom = atom->darray[index_];
}

void FixPropertyAtomLiggghts::reset_all_to_defaults(const std::vector<double> &defaults)
{
  defaults_ = defaults;
  for (int i = 0; i < atom->nlocal + atom->nghost; ++i) set_arrays(i);
}

FixPropertyAtomLiggghts *FixPropertyAtomLiggghts::find(LAMMPS *lmp, const std::string &name)
{
  for (Fix *f : lmp->modify->get_fix_by_style("^property/atom$")) {
    auto *p = dynamic_cast<FixPropertyAtomLiggghts *>(f);
    if (p && p->name_ == name) return p;
  }
  return nullptr;
}

void FixPropertyAtomLiggghts::grow_arrays(int nmax)
{
  if (scalar_) memory->grow(atom->dvector[index_], nmax, "property/atom:dvector");
  else memory->grow(atom->darray[index_], nmax, ncols(), "property/atom:darray");
  refresh_output();
}

void FixPropertyAtomLiggghts::copy_arrays(int i, int j, int)
{
  for (int c = 0; c < ncols(); ++c) put(j, c, get(i, c));
}

void FixPropertyAtomLiggghts::set_arrays(int i)
{
  for (int c = 0; c < ncols(); ++c) put(i, c, defaults_[c]);
}

int FixPropertyAtomLiggghts::pack_exchange(int i, double *buf)
{
  for (int c = 0; c < ncols(); ++c) buf[c] = get(i, c);
  return ncols();
}

int FixPropertyAtomLiggghts::unpack_exchange(int nlocal, double *buf)
{
  for (int c = 0; c < ncols(); ++c) put(nlocal, c, buf[c]);
  return ncols();
}

int FixPropertyAtomLiggghts::pack_border(int n, int *list, double *buf)
{
  int m = 0;
  for (int k = 0; k < n; ++k)
    for (int c = 0; c < ncols(); ++c) buf[m++] = get(list[k], c);
  return m;
}

int FixPropertyAtomLiggghts::unpack_border(int n, int first, double *buf)
{
  int m = 0;
  for (int i = first; i < first + n; ++i)
    for (int c = 0; c < ncols(); ++c) put(i, c, buf[m++]);
  return m;
}

int FixPropertyAtomLiggghts::pack_forward_comm(int n, int *list, double *buf, int, int *)
{
  return pack_border(n, list, buf);
}

void FixPropertyAtomLiggghts::unpack_forward_comm(int n, int first, double *buf) { unpack_border(n, first, buf); }

int FixPropertyAtomLiggghts::pack_reverse_comm(int n, int first, double *buf)
{
  int m = 0;
  for (int i = first; i < first + n; ++i)
    for (int c = 0; c < ncols(); ++c) buf[m++] = get(i, c);
  return m;
}

void FixPropertyAtomLiggghts::unpack_reverse_comm(int n, int *list, double *buf)
{
  int m = 0;
  for (int k = 0; k < n; ++k)
    for (int c = 0; c < ncols(); ++c) put(list[k], c, get(list[k], c) + buf[m++]);
}

int FixPropertyAtomLiggghts::pack_restart(int i, double *buf)
{
  buf[0] = ncols() + 1;
  for (int c = 0; c < ncols(); ++c) buf[c + 1] = get(i, c);
  return ncols() + 1;
}

void FixPropertyAtomLiggghts::unpack_restart(int nlocal, int nth)
{
  double **extra = atom->extra;
  int m = 0;
  for (int k = 0; k < nth; ++k) m += static_cast<int>(extra[nlocal][m]);
  m++;
  for (int c = 0; c < ncols(); ++c) put(nlocal, c, extra[nlocal][m++]);
}

double FixPropertyAtomLiggghts::memory_usage() { return double(atom->nmax) * ncols() * sizeof(double); }

void FixPropertyAtomLiggghts::forward_comm() { comm->forward_comm(this); }
void FixPropertyAtomLiggghts::reverse_comm() { comm->reverse_comm(this); }

// LIGGGHTS's form (NAME scalar|vector ...) here, LAMMPS's own (i_/d_/mol/q/...) to the built-in.
static FixFactory builtin_property_atom = nullptr;

static void *create_property_atom(void *lmp, int narg, char **arg)
{
  auto *l = static_cast<LAMMPS *>(lmp);
  if (FixPropertyAtomLiggghts::is_liggghts_syntax(narg, arg)) return new FixPropertyAtomLiggghts(l, narg, arg);
  if (!builtin_property_atom)
    l->error->all(FLERR, "fix " + std::string(arg[0]) + " property/atom: this LAMMPS has no built-in fix property/atom");
  return builtin_property_atom(lmp, narg, arg);
}

static RegisterStyle reg_property_atom("fix", "property/atom",
                                       "LIGGGHTS property/atom NAME scalar|vector ... (LAMMPS's own syntax goes to the built-in)",
                                       create_property_atom, &builtin_property_atom);

}  // namespace dembridge
