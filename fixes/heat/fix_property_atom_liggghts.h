// fix ID group property/atom NAME scalar|vector restart commghost commrev default...: LIGGGHTS's
// per-atom property. The values live in a LAMMPS custom per-atom property called NAME (d_NAME for a
// scalar, d2_NAME for a vector), so LAMMPS's `set ... d_NAME V`, `compute property/atom d_NAME` and
// this fix's own per-atom output f_ID all see them. LAMMPS's syntax (i_/d_/mol/q/...) goes to the
// built-in fix property/atom.
#pragma once

#include "fix.h"

#include <string>
#include <vector>

namespace dembridge {

class FixPropertyAtomLiggghts : public LAMMPS_NS::Fix {
 public:
  FixPropertyAtomLiggghts(LAMMPS_NS::LAMMPS *lmp, int narg, char **arg);
  ~FixPropertyAtomLiggghts() override;
  int setmask() override { return 0; }

  // True for the LIGGGHTS form (the word after NAME is scalar or vector).
  static bool is_liggghts_syntax(int narg, char **arg);

  const std::string &name() const { return name_; }
  int ncols() const { return int(defaults_.size()); }
  bool is_scalar() const { return scalar_; }
  double *values();   // scalar: one per atom
  double **rows();    // vector: ncols per atom
  void reset_all_to_defaults(const std::vector<double> &defaults);

  // The property/atom fix of LIGGGHTS name `name` (nullptr if none).
  static FixPropertyAtomLiggghts *find(LAMMPS_NS::LAMMPS *lmp, const std::string &name);

  void grow_arrays(int nmax) override;
  void copy_arrays(int i, int j, int delflag) override;
  void set_arrays(int i) override;
  int pack_exchange(int i, double *buf) override;
  int unpack_exchange(int nlocal, double *buf) override;
  int pack_border(int n, int *list, double *buf) override;
  int unpack_border(int n, int first, double *buf) override;
  int pack_forward_comm(int n, int *list, double *buf, int pbc_flag, int *pbc) override;
  void unpack_forward_comm(int n, int first, double *buf) override;
  int pack_reverse_comm(int n, int first, double *buf) override;
  void unpack_reverse_comm(int n, int *list, double *buf) override;
  int pack_restart(int i, double *buf) override;
  void unpack_restart(int nlocal, int nth) override;
  int maxsize_restart() override { return ncols() + 1; }
  int size_restart(int) override { return ncols() + 1; }
  double memory_usage() override;

  void forward_comm();  // ghosts get their owners' values
  void reverse_comm();  // ghost values are added to their owners'

 private:
  double get(int i, int c);
  void put(int i, int c, double v);
  void refresh_output();

  std::string name_;
  bool scalar_ = true;
  bool ghost_ = false;
  std::vector<double> defaults_;
  int index_ = -1;
};

}  // namespace dembridge
