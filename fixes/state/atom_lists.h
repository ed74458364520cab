// AtomLists: what the LAMMPS per-atom callbacks (PerAtomCallbacksFix) need of a fix's per-atom storage,
// LAMMPS-free. Implemented by RecordLists (Parmec fixes, fix wall/gran) and by the contact history's
// PartnerLists (one pool, rebuilt at every neighbour rebuild: doc/per_atom_state.md).
// Wire format of one atom: [n, then the values n stands for].
#pragma once

namespace dembridge::state {

class AtomLists {
 public:
  virtual ~AtomLists() = default;
  virtual void resize(int nmax) = 0;
  virtual void copy(int from, int to) = 0;
  virtual void clear(int i) = 0;  // no entries (a new atom)
  virtual int packed_size(int i) const = 0;
  virtual int pack(int i, double *buf) const = 0;    // returns the doubles written
  virtual int unpack(int i, const double *buf) = 0;  // returns the doubles read
  // Are these `size` doubles one atom packed in this layout? (A restart file written with another
  // record size or by an older version is not.)
  virtual bool is_packed_atom(const double *buf, int size) const = 0;
};

}  // namespace dembridge::state
