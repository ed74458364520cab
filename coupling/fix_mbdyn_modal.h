// fix mbdyn ... modal: LAMMPS as the peer of MBDyn's `external modal` force. The fix's atoms are
// carried by the modal node and deformed by the modes of its modal joint (FEM file), and answer
// the node's force and moment and one generalized force per mode. Loose or tight coupling. Created by
// fix mbdyn when its arguments name `modal` (fix_mbdyn.cpp). Syntax: doc/fix_mbdyn.md. Its restart
// record (fix_mbdyn_modal_restart.cpp) lets a run after read_restart continue the coupling.
#pragma once

#include "fix.h"

#include <memory>
#include <string>
#include <unordered_map>
#include <vector>

#include "mbdyn_deform_driver.h"
#include "modal_body.h"
#include "modal_message.h"

namespace dembridge::mbdyn {
class SocketTransport;
}

namespace dembridge {

class FixMBDynModal : public LAMMPS_NS::Fix {
 public:
  FixMBDynModal(LAMMPS_NS::LAMMPS *lmp, int narg, char **arg);
  ~FixMBDynModal() override;

  int setmask() override;
  void init() override;
  void setup_pre_exchange() override;
  void pre_exchange() override {}
  void setup(int vflag) override;
  void post_integrate() override;
  void post_force(int vflag) override;
  double compute_vector(int i) override;
  void write_restart(FILE *fp) override;
  void restart(char *buf) override;

 private:
  [[noreturn]] void fail(const std::string &why);
  void fail_if_rank0_failed(std::string err);
  void bind_atoms();
  bool receive();  // false: MBDyn ended the simulation
  void place_atoms();
  void bind_mesh();    // mesh MESH-ID: its vertices matched to the FEM nodes at the first pose
  void answer(bool converged);  // converged: command 6 (loose: always), else 2
  void iterate_tight(int vflag);
  void resume_coupling();  // the first set-up after read_restart: the restored binding, the mesh at the last pose
  void stop_peer();        // at the end: MBDyn's next message answered with 5, as fix mbdyn does
  static double kinematics_change(const mbdyn::ModalKinematics &a, const mbdyn::ModalKinematics &b);

  // configuration
  std::string path_;
  mbdyn::ModalConfig config_;
  mbdyn::FemModel fem_;
  std::string origin_;
  double match_ = 1e-6;
  std::string mesh_id_;                   // mesh MESH-ID: the FEM nodes drive its vertices
  std::unique_ptr<MbdynDeformDriver> deform_;
  double connect_timeout_ = 60, io_timeout_ = 300;
  bool tight_ = false, startup_exchange_ = true;
  double tolerance_ = 1e-9;  // tight: converged when no value of the message changed by more
  int max_iterations_ = 10;  // tight: at most this many exchanges per MBDyn step
  bool resume_ = true;       // read_restart: continue the restart file's coupling (resume yes)

  std::unique_ptr<mbdyn::SocketTransport> transport_;  // rank 0
  mbdyn::ModalBody body_;
  std::vector<LAMMPS_NS::tagint> tags_;                 // the carried atoms, point order
  std::unordered_map<LAMMPS_NS::tagint, std::size_t> point_of_;
  mbdyn::ModalKinematics kin_;
  std::vector<double> x_, v_;  // 3P per message
  std::vector<unsigned char> buf_;
  mbdyn::ModalLoads last_;
  bool bound_ = false, mesh_bound_ = false, ended_ = false, connected_ = false;
  bool first_is_step1_ = false;  // tight, no start-up exchange: the set-up's message is step 1's
  bool t0_answered_ = false;     // the start-up message was answered (a later run's set-up does not again)
  bool restored_ = false;        // read_restart gave the coupling state; resume_coupling() at the set-up
  bool failed_ = false;          // an error stops the run: no clean stop with MBDyn
  double last_change_ = 0;       // tight: change of the last iterate from the one before
  long long messages_ = 0;
};

}  // namespace dembridge
