// Glue for every dembridge granular pair style: neighbour loop, tallies, checks, restart of the
// settings. The physics is the ContactLaw (contact/), the coefficients the MaterialTable
// (materials/), the syntax the ModelDescription (syntax/).
#pragma once

#include "fix.h"
#include "pair.h"

#include "contact_law.h"
#include "pair_gran_kernel.h"
#include "material_table.h"
#include "model_syntax.h"

#include <cstddef>
#include <map>
#include <string>
#include <vector>

namespace dembridge {

class FixContactHistory;

class PairGran : public LAMMPS_NS::Pair {
 public:
  PairGran(LAMMPS_NS::LAMMPS *lmp, const char *style_name);
  ~PairGran() override;

  void compute(int eflag, int vflag) override;
  void settings(int narg, char **arg) override;
  void coeff(int narg, char **arg) override;
  void init_style() override;
  double init_one(int i, int j) override;
  void init_list(int id, LAMMPS_NS::NeighList *ptr) override;
  void write_restart(FILE *fp) override;
  // pair_modify timestep_check yes|no|F (pair_gran_timestep.cpp): an opt-in WARNING at run setup when dt
  // exceeds F times the Rayleigh or Hertz time of fix check/timestep/gran; other keywords go to LAMMPS.
  void modify_params(int narg, char **arg) override;
  void setup() override;
  int pack_forward_comm(int n, int *list, double *buf, int pbc_flag, int *pbc) override;
  void unpack_forward_comm(int n, int first, double *buf) override;
  void read_restart(FILE *fp) override;
  void write_restart_settings(FILE *fp) override;
  void read_restart_settings(FILE *fp) override;
  double memory_usage() override;  // LAMMPS's per-atom energy/virial arrays and the rigid-body masses (the history is its fix's)

 protected:
  // The neighbour loop, written once (pair_gran_contacts.h): evaluates the contacts of the list atoms
  // ilist[ii], ii in [ii_from, ii_to), in list order, updating their history, and hands each contact to
  // sink(i, j, ii, jj, res). It writes only those atoms' history slots, so disjoint ranges may run on
  // threads. Call begin_contacts() once before and end_contacts() once after the ranges of a step.
  template <class Sink> void for_each_contact(int ii_from, int ii_to, Sink &&sink);
  void begin_contacts();
  void end_contacts();
  // The arrays of this step for the loop (pair_gran_kernel.h); no side effects, cheap.
  gran::PairLoopData loop_data() const;
  [[noreturn]] void loop_failed(const gran::PairLoopError &e);
  const std::string &style_name() const { return style_name_; }
  bool force_on() const { return model_.force_on; }

 private:
  std::string style_name_;
  std::vector<std::string> settings_args_;  // kept for restart
  gran::ModelDescription model_;
  gran::ContactLaw law_;
  gran::MaterialTable table_;
  bool uniform_coeffs_ = false;  // table_.uniform(), once per init
  std::vector<double> maxrad_dynamic_, maxrad_frozen_;  // per type, for the cutoff
  int freeze_groupbit_ = 0;
  FixContactHistory *history_ = nullptr;
  LAMMPS_NS::Fix *fix_rigid_ = nullptr;  // body masses replace particle masses (spec §2)
  std::vector<double> mass_rigid_;        // per owned+ghost atom: its body's mass, 0 if none
  void update_rigid_masses();
  // Opt-in timing of the neighbour loop (pair_gran_probe.cpp, bench/run_pair_probe.py): DEMBRIDGE_PAIR_PROBE=
  // STEP[,PASSES] reruns STEP's loop PASSES times with each loop (AVX2, scalar) on scratch forces and copies
  // of the history, and prints the thread CPU times; the run itself is unchanged.
  long probe_step_ = -1;
  int probe_passes_ = 200;
  gran::PairLoopData::Scan forced_scan_ = gran::PairLoopData::Scan::Default;
  void read_probe_setting();  // from the environment, at init_style
  void probe_pair_loop();
  // The serial compute's loop over this step's contacts, each added to f and torque (the run's or the
  // probe's scratch arrays) by its ForceSink (pair_gran.cpp).
  void serial_contacts(double *f, double *torque);
  struct ForceSink;
  // Material properties kept in the restart file; a fix property/global of the same name wins.
  std::map<std::string, property::GlobalProperty> restart_properties_;

  const property::GlobalProperty *find_property(const std::string &name);
  double timestep_check_ = 0.0;  // pair_modify timestep_check: the fraction, 0 = off (default)
  std::string history_id_;  // ID of this style's history fix (empty: none yet)
  void reserve_history_place();
  std::string free_history_id() const;
  void create_history_fix();
  [[noreturn]] void degenerate_contact(int i, int j, bool coincident);
  void allocate();
  void check_requirements();
  int max_type_present();
  void compute_type_radii();
  void apply_settings(const std::vector<std::string> &args);

 public:
  // Read access for the per-contact compute (never mutates history).
  const gran::ContactLaw &law() const { return law_; }
  const gran::MaterialTable &table() const { return table_; }
  FixContactHistory *history() const { return history_; }
  double effective_mass(int i, int j) const;
  LAMMPS_NS::NeighList *neighbor_list() const { return list; }
};

}  // namespace dembridge
