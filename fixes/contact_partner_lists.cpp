#include "contact_partner_lists.h"

using LAMMPS_NS::tagint;
using LAMMPS_NS::ubuf;

namespace dembridge {

void PartnerLists::resize(int nmax)
{
  npartner.resize(nmax, 0);
  offset.resize(nmax, 0);
  own_tag.resize(nmax, 0);
}

void PartnerLists::copy(int from, int to)
{
  npartner[to] = npartner[from];
  offset[to] = offset[from];
  own_tag[to] = own_tag[from];
}

void PartnerLists::clear(int i)
{
  npartner[i] = 0;
  offset[i] = 0;
  own_tag[i] = 0;  // a new atom: its tag may not be assigned yet, and it has no partners
}

int PartnerLists::pack(int i, double *buf) const
{
  int m = 0;
  buf[m++] = npartner[i];
  for (int k = 0; k < npartner[i]; k++) {
    buf[m++] = ubuf(pool_tag[offset[i] + k]).d;
    for (int q = 0; q < nv_; q++) buf[m++] = pool_val[(offset[i] + k) * nv_ + q];
  }
  return m;
}

int PartnerLists::unpack(int i, const double *buf)
{
  int m = 0;
  const int n = static_cast<int>(buf[m++]);
  npartner[i] = n;
  offset[i] = pool_tag.size();
  for (int k = 0; k < n; k++) {
    pool_tag.push_back(static_cast<tagint>(ubuf(buf[m++]).i));
    for (int q = 0; q < nv_; q++) pool_val.push_back(buf[m++]);
  }
  own_tag[i] = (*atom_tag_)[i];
  return m;
}

bool PartnerLists::is_packed_atom(const double *buf, int size) const
{
  if (size < 1) return false;
  const int n = static_cast<int>(buf[0]);
  return n >= 0 && size == 1 + n * (1 + nv_);
}

}  // namespace dembridge
