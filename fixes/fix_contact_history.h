// Per-contact history (shear and rolling springs) for the dembridge granular pair styles.
// During a run the values live in neighbour-list order (one slot per list entry); only when atoms
// migrate, are sorted, or a restart is written are they converted to per-atom partner lists
// (partner tag + values, the partner's copy negated) that move with the atoms (spec
// lammps-toolchain §4-§5: list order avoids the 24 % wall-time cost of per-atom look-ups).
// Created and owned by the pair style; users never define it.
#pragma once

#include "fix.h"

#include <vector>

namespace dembridge {

class FixContactHistory : public LAMMPS_NS::Fix {
 public:
  // args: ID group dembridge/contact/history NVALUES
  FixContactHistory(LAMMPS_NS::LAMMPS *lmp, int narg, char **arg);
  ~FixContactHistory() override;
  int setmask() override;
  void setup_pre_exchange() override { pre_exchange(); }
  void setup_post_neighbor() override { post_neighbor(); }
  void min_pre_exchange() override { pre_exchange(); }
  void min_post_neighbor() override { post_neighbor(); }
  void pre_exchange() override;
  void post_neighbor() override;
  void post_run() override;

  int nvalues() const { return nv_; }
  void set_list(LAMMPS_NS::NeighList *list) { list_ = list; }
  // Slot of the jj-th neighbour of local atom i; valid between post_neighbor and pre_exchange.
  double *slot(int i, int jj) { return &values_[(first_[i] + jj) * nv_]; }
  unsigned char &touched(int i, int jj) { return touch_[first_[i] + jj]; }
  bool list_valid() const { return list_valid_; }
  void mark_updated() { atoms_stale_ = true; }  // the pair changed list values this step

  void grow_arrays(int nmax) override;
  void copy_arrays(int i, int j, int delflag) override;
  void set_arrays(int i) override { npartner_[i] = 0; }
  int pack_exchange(int i, double *buf) override;
  int unpack_exchange(int nlocal, double *buf) override;
  int pack_restart(int i, double *buf) override;
  void unpack_restart(int nlocal, int nth) override;
  int size_restart(int i) override;
  int maxsize_restart() override;
  double memory_usage() override;

  // Per-atom view for tests/diagnostics: number of partners of local atom i, and the k-th.
  int npartner(int i) const { return npartner_[i]; }
  LAMMPS_NS::tagint partner(int i, int k) const { return partner_[std::size_t(i) * cap_ + k]; }
  const double *partner_values(int i, int k) const { return &pvalues_[(std::size_t(i) * cap_ + k) * nv_]; }

 private:
  int nv_;
  LAMMPS_NS::NeighList *list_ = nullptr;
  bool list_valid_ = false;   // list-order slots hold the current history
  bool atoms_stale_ = false;  // per-atom lists are older than the list-order slots
  std::vector<int> first_;
  std::vector<double> values_;
  std::vector<unsigned char> touch_;
  int cap_ = 8;  // partners per atom before re-striding
  int nmax_ = 0;
  std::vector<int> npartner_;
  std::vector<LAMMPS_NS::tagint> partner_;
  std::vector<double> pvalues_;

  void atoms_from_list();
  void sync_atoms();
  int pack_partners(int i, double *buf) const;
  int unpack_partners(int i, const double *buf);
  void list_from_atoms();
  void add_partner(int i, LAMMPS_NS::tagint tag, const double *v, double sign);
  void grow_capacity(int need);
};

}  // namespace dembridge
