#include "local_incidence.h"

#include <algorithm>

namespace dembridge::state {

bool LocalIncidence::update(int nlocal, int n, const int *keys, const int *atom1, const int *atom2)
{
  if (nlocal == nlocal_ && n == static_cast<int>(keys_.size()) && std::equal(keys, keys + n, keys_.begin()) &&
      std::equal(atom1, atom1 + n, atom1_.begin()) && std::equal(atom2, atom2 + n, atom2_.begin()))
    return false;
  nlocal_ = nlocal;
  keys_.assign(keys, keys + n);
  atom1_.assign(atom1, atom1 + n);
  atom2_.assign(atom2, atom2 + n);
  offset_.assign(nlocal + 1, 0);
  for (int r = 0; r < n; r++) {
    if (atom1[r] >= 0) offset_[atom1[r] + 1]++;
    if (atom2[r] >= 0) offset_[atom2[r] + 1]++;
  }
  for (int i = 0; i < nlocal; i++) offset_[i + 1] += offset_[i];
  terms_.resize(offset_[nlocal]);
  std::vector<int> fill(offset_.begin(), offset_.end() - 1);
  for (int r = 0; r < n; r++) {
    if (atom1[r] >= 0) terms_[fill[atom1[r]]++] = {keys[r], r, 0};
    if (atom2[r] >= 0) terms_[fill[atom2[r]]++] = {keys[r], r, 1};
  }
  for (int i = 0; i < nlocal; i++)
    std::sort(terms_.begin() + offset_[i], terms_.begin() + offset_[i + 1],
              [](const Term &a, const Term &b) { return a.key < b.key; });
  return true;
}

}  // namespace dembridge::state
