// fix parmec/rigid: Parmec's time integrator for rigid bodies (spec parmec-springs §1, §10; user page
// doc/fix_parmec_rigid.md) with RESTRAIN, PRESCRIBE, DAMPING and time-dependent GRAVITY.
//
// Design: each atom is one Parmec particle (mass rmass, referential inertia tensor from a per-atom
// property or the sphere's 0.4 m r²). The rotation Λ (9 values, so Parmec's slightly non-orthogonal Q3
// matrices can be reproduced) and the body angular velocity Ω are one record per body on the per-atom
// state layer (fixes/state, doc/per_atom_state.md): the bodies are the group's atoms when the fix is
// defined, and their records follow them through exchange, sorting and restart. Forces of the other fixes are
// evaluated at (x_{n+1/2}, Λ_{n+1/2}, v_n, ω_n); final_integrate applies gravity, restraints,
// prescriptions and damping and then kicks and drifts (v_{n+1}, x_{n+3/2}), so the state after LAMMPS
// step m is Parmec's HISTORY row of step m-1. Restraints and prescriptions are few and replicated
// (atom tag -> definition).
#pragma once

#include "body_inertia.h"
#include "per_atom_state_fix.h"

#include "body_rotation.h"
#include "joint_solver.h"
#include "time_series.h"

#include <map>
#include <memory>
#include <string>
#include <vector>

namespace dembridge {

class FixParmecRigid : public state::PerAtomStateFix {
 public:
  FixParmecRigid(LAMMPS_NS::LAMMPS *lmp, int narg, char **arg);
  ~FixParmecRigid() override;
  int setmask() override;
  void init() override;
  void setup(int) override;
  void setup_pre_exchange() override;
  void pre_exchange() override {}
  void setup_pre_force(int) override;
  void pre_force(int) override;
  int pack_forward_comm(int n, int *list, double *buf, int pbc_flag, int *pbc) override;
  void unpack_forward_comm(int n, int first, double *buf) override;
  void final_integrate() override;
  void write_restart(FILE *fp) override;
  void restart(char *buf) override;
  double compute_array(int i, int j) override;
  int modify_param(int narg, char **arg) override;
  void grow_arrays(int nmax) override;

  // Record of a body: key, "fresh" (1 until Λ and Ω are taken from the atom at the first setup), Λ
  // (row-major), Ω.
  static constexpr int kRecord = 1 + 1 + 9 + 3;

 protected:
  void evaluate(Mode) override {}  // an integrator: no per-step force evaluation

 private:
  // A time-dependent scalar: constant, TSERIES (clamped, Parmec's TMS_Value) or equal-style variable.
  struct Series {
    int kind = 0;  // 0 constant, 1 tseries, 2 variable
    double value = 0.0;
    std::string name;
    const springs::TimeSeries *ts = nullptr;
    int ivar = -1;
  };
  struct Restraint {
    rigid::Vec3 lin[3], ang[3];
    int nlin = 0, nang = 0;
  };
  struct Prescription {
    bool lin = false, ang = false;
    bool lin_acc = false, ang_acc = false;  // 'a' kinds
    Series l[3], a[3];
  };

  void parse(const std::vector<std::string> &tok, const std::string &where);
  Series parse_series(const std::string &word, const std::string &what, const std::string &where);
  void resolve(Series &s, const std::string &what);
  void resolve_all();
  double eval(const Series &s, double t);
  void restrain_velocities();
  void half_drift();
  void find_inertia();
  double *body_record(int i);  // the record of local atom i, nullptr if it is not a body
  double *lam(int i) { return body_record(i) + 2; }
  double *omg(int i) { return body_record(i) + 11; }
  void define_bodies();
  void fill_rotation_output();
  double step_time() const;  // t_n of the step being integrated
  void setup_joints();       // body list, clusters, arms (first run: from the reference configuration)
  void apply_joints(std::vector<rigid::Vec3> &F0, std::vector<rigid::Vec3> &T0, const double *dl, const double *da,
                    double tv);
  rigid::Mat3 inertia(int i) const;
  void check_inertia();  // ERROR for a body whose inertia tensor is not positive definite

  std::map<std::string, springs::TimeSeries> tseries_;
  bool has_gravity_ = false, has_damping_ = false;
  Series gravity_[3], damp_lin_[3], damp_ang_[3];
  std::map<LAMMPS_NS::tagint, Restraint> restraints_;
  std::map<LAMMPS_NS::tagint, Prescription> prescriptions_;
  state::BodyInertia inertia_;  // 'inertia NAME' (d2_ property with 6 columns), else the sphere's
  bool q1_ = false, q2_ = false, q3_ = false, q20_ = false, qj_ = false;
  bool half_drift_ = true;
  int started_ = 0;  // initial half drift done (restart keeps it)
  double curtime_ = 0.0;  // Parmec's accumulated time t_n of the next step
  bool redefine_ = false; // fix_modify: tseries and prescriptions may be replaced
  struct JointInput {
    long id = 0;
    LAMMPS_NS::tagint tag1 = 0, tag2 = -1;
    double point[3] = {0, 0, 0};
  };
  std::vector<JointInput> joint_in_;
  std::vector<LAMMPS_NS::tagint> body_tags_;  // jointed bodies, sorted by tag
  std::map<LAMMPS_NS::tagint, int> body_index_;
  std::vector<rigid::Vec3> arms_;             // 2 per joint (body frame), from the reference configuration
  std::unique_ptr<rigid::JointClusters> clusters_;
  std::vector<rigid::Vec3> reactions_;
  bool q16_ = false;
  bool q26_ = false;  // 'taylor parmec': the ISPC kernels' single-precision series coefficients
  std::string joint_file_;
  FILE *joint_fp_ = nullptr;
  double **J_ = nullptr;
  // Λ row-major per atom (f_ID[1..9]): local atoms from the records, ghosts by forward communication
  // before the forces of every step, so force fixes can use Parmec's stored rotation on both atoms of a
  // two-atom entity (fix parmec/spring 'order parmec')
  double **rot_out_ = nullptr;
  void share_rotations();
  void add_gravity();
};

}  // namespace dembridge
