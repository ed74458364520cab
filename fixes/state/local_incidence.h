// Which evaluated entities touch each local atom, in key order (LAMMPS-free; doc/per_atom_state.md).
//
// A fix that evaluates its entities into per-evaluation results (index r) can sum each local atom's
// contributions in key order straight from those results, instead of storing an entry per atom and
// sorting it every step. The lists depend only on (key, first atom, second atom) of every evaluation,
// which change only when atoms migrate, are sorted or are re-neighboured: update() compares them and
// rebuilds only then.
#pragma once

#include <vector>

namespace dembridge::state {

class LocalIncidence {
 public:
  struct Term {
    int key;   // entity key (the summation order)
    int r;     // evaluation index
    int side;  // 0: the entity's first atom, 1: its second
  };

  // Evaluation r touches local atoms atom1[r] and atom2[r] (-1: not a local atom, or no contribution).
  // Rebuilds the lists unless they were built from the same n triples; returns whether it rebuilt.
  bool update(int nlocal, int n, const int *keys, const int *atom1, const int *atom2);

  const Term *begin(int i) const { return terms_.data() + offset_[i]; }
  const Term *end(int i) const { return terms_.data() + offset_[i + 1]; }
  double bytes() const
  {
    return double(keys_.capacity() + atom1_.capacity() + atom2_.capacity() + offset_.capacity()) * sizeof(int) +
        double(terms_.capacity()) * sizeof(Term);
  }

 private:
  int nlocal_ = -1;
  std::vector<int> keys_, atom1_, atom2_;
  std::vector<int> offset_;
  std::vector<Term> terms_;
};

}  // namespace dembridge::state
