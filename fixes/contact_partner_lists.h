// PartnerLists: the per-atom contact lists of fix dembridge/contact/history between neighbour rebuilds.
// Atom i's partners are npartner[i] entries at offset[i] of one pool (partner tags in pool_tag, nv values
// each in pool_val); copies share a run (runs are never modified, only rebuilt), exchange and restart append.
// The fix rebuilds the whole pool at every neighbour rebuild: one pool written in two passes, not a list per
// atom (RecordLists would cost +9.2 M Ir per rebuild of the chute, ~1 %). Moved with the atoms by
// PerAtomCallbacksFix; wire format of one atom [n, tag_1, values_1..., tag_n, values_n...].
#pragma once

#include "atom_lists.h"
#include "lmptype.h"

#include <cstddef>
#include <vector>

namespace dembridge {

class PartnerLists final : public state::AtomLists {
 public:
  // atom_tag: where LAMMPS keeps the tag array (&atom->tag; the array moves when it grows).
  PartnerLists(int nv, LAMMPS_NS::tagint *const *atom_tag) : nv_(nv), atom_tag_(atom_tag) {}

  void resize(int nmax) override;
  void copy(int from, int to) override;
  void clear(int i) override;
  int packed_size(int i) const override { return 1 + npartner[i] * (1 + nv_); }
  int pack(int i, double *buf) const override;
  int unpack(int i, const double *buf) override;  // also records the atom's tag (own_tag)
  bool is_packed_atom(const double *buf, int size) const override;

  // per atom
  std::vector<int> npartner;
  std::vector<std::size_t> offset;
  std::vector<LAMMPS_NS::tagint> own_tag;  // the atom's tag when its list was written (0: unknown)
  // the pool
  std::vector<LAMMPS_NS::tagint> pool_tag;
  std::vector<double> pool_val;

 private:
  int nv_;
  LAMMPS_NS::tagint *const *atom_tag_;
};

}  // namespace dembridge
