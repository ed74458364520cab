// PerAtomStateFix: the LAMMPS side of the per-atom state layer (doc/per_atom_state.md), written once for
// the Parmec fixes (springs, torsion springs, joints, restraints) and any fix whose entities keep
// evolving state on one of their atoms.
//
// A derived fix defines its entities (replicated on every rank, indexed 0..n-1 in definition order),
// appends one record per entity to the atom that owns its state (records_.append), and evaluates them
// each step. This class does the rest: the records follow their atom through exchange, sorting, deletion
// and restart files; contributions to ghost atoms return to their owners and are summed in entity order
// (sums_); the global restart block, the state count check, the ghost cutoff that keeps the second atom of
// every two-atom entity in reach of the first one's owner (raised when an entity gets longer, see
// setup_pre_exchange and pre_exchange) and the per-entity CSV history are here too.
#pragma once

#include "atom.h"
#include "domain.h"

#include "definition_reader.h"
#include "ordered_sums.h"
#include "per_atom_records_fix.h"

#include <cstdio>
#include <functional>
#include <string>
#include <unordered_map>
#include <vector>

namespace dembridge::state {

// The atoms of the entities at definition time: per tag, found (1/0), unwrapped position and
// quaternion (1 0 0 0 without quaternions). Collective; tags < 0 are skipped.
struct AtomSnapshot {
  bool found = false;
  double x[3] = {0, 0, 0};
  double q[4] = {1, 0, 0, 0};
};
std::vector<AtomSnapshot> snapshot_atoms(LAMMPS_NS::LAMMPS *lmp, const std::vector<long> &tags);

// 'history FILE N ID ...': a CSV row per N steps of chosen columns per entity, written by rank 0.
class HistoryCsv {
 public:
  HistoryCsv() = default;
  HistoryCsv(const HistoryCsv &) = delete;
  HistoryCsv &operator=(const HistoryCsv &) = delete;
  ~HistoryCsv();
  // Collective. keys: the recorded entities' keys, ids their user IDs (header "TIME,<prefix><id>_<column>").
  void open(LAMMPS_NS::LAMMPS *lmp, const std::string &cmd, const std::string &file, const std::string &prefix,
            const std::vector<int> &keys, const std::vector<long> &ids, const std::vector<const char *> &columns);
  // Where the values of an entity go in a row (nullptr if it is not recorded); row() is zeroed first.
  double *values_of(int key);
  void begin_row();
  bool is_open() const;  // on every rank once open() ran
  // Collective: the rows of all ranks summed (each entity filled by its owner only), written by rank 0.
  void write_row(LAMMPS_NS::LAMMPS *lmp, double time);

 private:
  FILE *fp_ = nullptr;
  std::size_t ncols_ = 0;
  std::unordered_map<int, int> group_;  // key -> column group
  std::vector<double> row_, sum_;
};

class PerAtomStateFix : public PerAtomRecordsFix {
 public:
  // record_size: doubles per record, key included. Sets restart_global (PerAtomRecordsFix the rest).
  PerAtomStateFix(LAMMPS_NS::LAMMPS *lmp, int narg, char **arg, int record_size);
  ~PerAtomStateFix() override;

  // Evaluation modes, dispatched here: post_force commits a step, min_setup/min_post_force evaluate a
  // trial (minimisation, state unchanged); the derived setup() calls evaluate(Mode::Setup).
  enum class Mode { Commit, Trial, Setup };
  // POST_FORCE, MIN_POST_FORCE, END_OF_STEP with a history file, (MIN_)PRE_EXCHANGE with two-atom entities
  int setmask() override;
  // Two-atom entities: before the exchange and borders of a run's set-up or of a re-neighbouring, the ghost
  // cutoff is raised if an entity is longer (see "Reach" below)
  void setup_pre_exchange() override;
  void pre_exchange() override;
  void min_pre_exchange() override { pre_exchange(); }
  void post_force(int) override { evaluate(Mode::Commit); }
  void min_post_force(int) override { evaluate(Mode::Trial); }
  void min_setup(int) override { evaluate(Mode::Trial); }
  void end_of_step() override;  // the history row

  int pack_reverse_comm(int n, int first, double *buf) override;
  void unpack_reverse_comm(int n, int *list, double *buf) override;
  double memory_usage() override;

 protected:
  OrderedSums sums_;

  virtual void evaluate(Mode mode) = 0;
  // The history columns of one record (see open_history).
  virtual void history_values(const double *rec, double *out) const { (void)rec, (void)out; }

  // After the definitions. noun: what an entity is called in messages ("spring"); ids: the user IDs
  // in key (definition) order; atoms: (first atom tag, second atom tag or -1) per key. An entity's state
  // is a record of its first atom. width: values it contributes to each of its atoms per evaluation
  // (summed in key order by sums_).
  void define_entities(const std::string &noun, const std::vector<long> &ids,
                       const std::vector<std::pair<long, long>> &atoms, int width);
  int entity_count() const { return static_cast<int>(ids_.size()); }
  const std::vector<long> &entity_ids() const { return ids_; }
  bool two_atom_entities() const { return two_atom_; }
  std::string who(int key) const { return noun_ + " " + std::to_string(ids_[key]); }  // "spring 7"
  // A fresh record per entity on the local atoms that own one (their old records dropped).
  void initial_records(const std::function<void(int key, double *rec)> &init);
  // Collective: snapshots of the entities' atoms (2 per key: first, second); ERROR naming the entity
  // if one does not exist.
  std::vector<AtomSnapshot> snapshot_entity_atoms();
  // The local or ghost index of the second atom of entity key evaluated on local atom i (closest image
  // if asked); ERROR if it is not there (hint: how to fix it, appended).
  // Not thread-safe when it fails (ERROR); second_atom_or_missing is, returning -1 instead.
  int second_atom(int key, int i, bool closest_image, const char *hint = "");
  int second_atom_or_missing(int key, int i, bool closest_image) const;
  [[noreturn]] void second_atom_missing(int key, const char *hint);

  // init(): ERROR under run_style respa, and for two-atom entities without an atom map or without ghost
  // velocities (ghost_velocities: "<entities> between two atoms need ghost <what>", the message's start).
  void check_run_style_and_ghosts(const std::string &ghost_velocities);
  // Collective: ERROR unless the records held by all ranks are one per entity.
  void check_record_count();
  // Collective: the two-atom entity whose atoms are farthest apart beyond `cutoff` (key -1: none).
  struct Farthest {
    int key = -1;
    double distance = 0.0;
  };
  Farthest farthest_beyond(double cutoff);

  // Reach of the second atoms (two-atom entities): the ghost cutoff is raised at a run's set-up (lengths from
  // the owners' positions) and at a re-neighbouring (lengths from this step's ghost positions, measured only if
  // an evaluation since the last one met an entity longer than near_length()) to twice the longest entity
  // when one is longer than the cutoff, so that every second atom is a ghost of its first atom's owner until
  // the next re-neighbouring, whatever its length. An evaluation calls note_near() when it met a pair of atoms
  // farther apart than near_length() (the ghost cutoff less the neighbour skin, at least half the cutoff).
  double near_length() const { return near_; }
  void note_near() { near_seen_ = true; }

  // Ordered sums of one evaluation: reset, contribute (sign * values to atom i, local or ghost), then
  // collect (reverse communication when two-atom entities exist) and sums_.sum(i) per local atom.
  void reset_sums();
  void contribute(int i, int key, const double *values, double sign)
  {
    if (!sums_.add(i, key, values, sign)) contribution_overflow();
  }
  void collect_sums();

  // The global restart block of the entities' reference data: [n * sign, n x (first tag, second tag,
  // `per` values)]. sign -1 marks a layout version. read_entity_restart ERRORs unless the tags match
  // the definitions; per_of(negative) gives the values per entity of the layout read.
  void write_entity_restart(FILE *fp, int per, double sign, const std::function<void(int key, double *o)> &fill);
  void read_entity_restart(const char *buf, const std::function<int(bool negative)> &per_of,
                           const std::function<void(int key, const double *o, int per)> &apply);

  // Local output: cols per row; local_rows(n) sizes array_local (grown geometrically) for n rows.
  void local_output(int cols);
  void local_rows(int n);

  // 'history FILE N ID ...' (DefinitionReader::history) after define_entities: a CSV row every N steps
  // (end_of_step) with `columns` per recorded entity (header "<prefix><id>_<column>").
  void open_history(const DefinitionReader::History &request, const std::string &prefix,
                    const std::vector<const char *> &columns);
  HistoryCsv history_;

 private:
  int maxlocal_ = 0;  // rows allocated in array_local
  std::string noun_;
  std::vector<long> ids_;
  std::vector<std::pair<long, long>> atoms_;
  std::unordered_map<long, std::vector<int>> by_first_;  // first atom tag -> keys
  bool two_atom_ = false;
  double near_ = 0.0;        // near_of(the ghost cutoff in effect)
  bool near_seen_ = false;   // an evaluation since the last re-neighbouring met a pair beyond near_
  [[noreturn]] void contribution_overflow();
  // Raise the ghost cutoff (from cutoff) to twice far.distance and say so; returns the new cutoff
  double raise_ghost_cutoff(double cutoff, const Farthest &far);
  double near_of(double cutoff) const;

 protected:
  // Whether a record read from a restart file belongs to atom i (default: its key is an entity whose first
  // atom is i). Fixes whose records are created on the fly (contacts keyed by the partner) override it.
  virtual bool restored_record_fits(int i, const double *rec) const;
  void check_restored(int i) override;
};

// Inline: evaluated for every two-atom entity every step (Atom::map is virtual; the array map is read
// directly).
inline int PerAtomStateFix::second_atom_or_missing(int key, int i, bool closest_image) const
{
  const LAMMPS_NS::tagint tag2 = atoms_[key].second;
  int k = atom->map_style == LAMMPS_NS::Atom::MAP_ARRAY ? (tag2 <= atom->map_tag_max ? atom->get_map_array()[tag2] : -1)
                                                        : atom->map(tag2);
  if (k >= 0 && closest_image && (domain->xperiodic || domain->yperiodic || domain->zperiodic))
    k = domain->closest_image(i, k);
  return k;
}

}  // namespace dembridge::state
