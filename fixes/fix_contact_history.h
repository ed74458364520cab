// Per-contact history (shear and rolling springs) for the dembridge granular pair styles.
// During a run the values live in neighbour-list order (one slot per list entry); only when atoms
// migrate, are sorted, or a restart is written are they converted to per-atom partner lists
// (partner tag + values, the partner's copy negated) that move with the atoms (spec
// lammps-toolchain §4-§5: list order avoids the 24 % wall-time cost of per-atom look-ups).
//
// Robust to other fixes: the conversion to per-atom lists reads the tags the neighbour list was
// built with (not the live arrays, which a fix pour / deposit / evaporate placed before this one
// may already have changed in pre_exchange) and finds the atoms by tag. Between runs, renumbered
// atom IDs (delete_atoms compress yes) are followed; partners that no longer exist are dropped.
//
// Memory: the per-atom lists are one packed pool (PartnerLists; the LAMMPS per-atom callbacks that move
// them are PerAtomCallbacksFix's) rebuilt at every conversion, so it is sized by
// the contacts present (no per-atom stride set by the busiest atom); the list-order arrays shrink
// when the neighbour list does. An array whose old values are dead is released before it grows (never
// old and new copies at once: at 10^6 atoms in 12 contacts each that copy was 150 B per atom of peak RSS).
//
// Created and owned by a pair style (one per history-carrying sub-style of pair hybrid); users
// never define it. Global vector for tests and benchmarks (sums over ranks): [1] bytes in use,
// [2] contacts stored, [3] list-order slots, [4] bytes of the contact storage alone.
#pragma once

#include "contact_partner_lists.h"
#include "per_atom_callbacks_fix.h"
#include "touch_flag.h"

#include <vector>

namespace dembridge {

class FixContactHistory : public state::PerAtomCallbacksFix {
 public:
  // args: ID group dembridge/contact/history NVALUES
  FixContactHistory(LAMMPS_NS::LAMMPS *lmp, int narg, char **arg);
  int setmask() override;
  void setup_pre_exchange() override;
  void setup_post_neighbor() override { post_neighbor(); }
  void min_pre_exchange() override { pre_exchange(); }
  void min_post_neighbor() override { post_neighbor(); }
  void pre_exchange() override;
  void post_neighbor() override;
  void post_run() override;
  double compute_vector(int n) override;

  int nvalues() const { return nv_; }
  void set_list(LAMMPS_NS::NeighList *list) { list_ = list; }
  // Slot of the jj-th neighbour of local atom i; valid between post_neighbor and pre_exchange.
  double *slot(int i, int jj) { return &values_[(first_[i] + jj) * nv_]; }
  gran::TouchFlag &touched(int i, int jj) { return touch_[first_[i] + jj]; }
  bool list_valid() const { return list_valid_; }
  // The list-order arrays themselves (the pair loop indexes them with first_slots()).
  double *values() { return values_.data(); }
  gran::TouchFlag *touch_flags() { return touch_.data(); }
  const std::size_t *first_slots() const { return first_.data(); }
  std::size_t slot_count() const { return slots_; }  // list-order slots (values() holds nvalues() per slot)
  void mark_updated() { atoms_stale_ = true; }  // the pair changed list values this step

  double memory_usage() override;

  // Per-atom view for tests/diagnostics: number of partners of local atom i, and the k-th.
  int npartner(int i) const { return partners_.npartner[i]; }
  LAMMPS_NS::tagint partner(int i, int k) const { return partners_.pool_tag[partners_.offset[i] + k]; }
  const double *partner_values(int i, int k) const { return &partners_.pool_val[(partners_.offset[i] + k) * nv_]; }

 protected:
  // PerAtomCallbacksFix's hooks: a restart mid-run needs the per-atom lists of this step (sync_atoms);
  // restored lists replace the list-order slots; another model's restart data: warn, no history.
  void flush_records() override { sync_atoms(); }
  void check_restored(int i) override;
  void restart_mismatch(int i) override;

 private:
  const int nv_;
  LAMMPS_NS::NeighList *list_ = nullptr;
  bool list_valid_ = false;   // list-order slots hold the current history
  bool atoms_stale_ = false;  // per-atom lists are older than the list-order slots
  bool mismatch_warned_ = false;

  // list order, with the tags and the owned-atom count the list was built with
  std::vector<std::size_t> first_;
  std::vector<double> values_;
  std::vector<gran::TouchFlag> touch_;  // slots_ flags and kTouchPadding more
  std::size_t slots_ = 0;
  std::vector<LAMMPS_NS::tagint> list_tag_;
  int list_nlocal_ = 0;

  // per atom: a run of npartner[i] entries at offset[i] of the pool (copies share runs)
  PartnerLists partners_;

  // global vector, reduced once per call site
  double stats_[4] = {0, 0, 0, 0};

  void atoms_from_list();
  void sync_atoms();
  void list_from_atoms();
  void follow_renumbered_tags();
  void compact_pool();
  void set_maxexchange(int most_partners);
  std::size_t live_entries() const;
  std::size_t list_entries() const;
  double contact_bytes(std::size_t entries) const;
};

}  // namespace dembridge
