// fix mbdyn: LAMMPS as the peer of MBDyn's `external structural` force (issue 6).
// Each MBDyn point is mapped to one atom or to a rigid group of atoms that follows the point's
// pose and velocity; the loads the coupled atoms feel are summed about the point, reduced over
// the MPI ranks and sent back. Loose coupling with sub-cycling, tight coupling with force
// re-evaluation. Syntax and timelines: doc/fix_mbdyn.md.
#pragma once

#include "fix.h"

#include <array>
#include <memory>
#include <string>
#include <unordered_map>
#include <vector>

#include "exchange_profile.h"
#include "mbdyn_deform_driver.h"
#include "mbdyn_mesh_driver.h"

namespace dembridge::mbdyn {
class PeerSession;
class FileSession;
struct FileOptions;
class SocketListener;
struct SessionOptions;
struct Kinematics;
struct Loads;
}  // namespace dembridge::mbdyn

namespace dembridge {

class FixMBDyn : public LAMMPS_NS::Fix {
 public:
  FixMBDyn(LAMMPS_NS::LAMMPS *lmp, int narg, char **arg);
  ~FixMBDyn() override;

  int setmask() override;
  void init() override;
  void setup_pre_exchange() override;
  void setup(int vflag) override;
  void pre_exchange() override {}
  void post_integrate() override;
  void post_force(int vflag) override;
  void end_of_step() override;
  void post_run() override;

  double compute_vector(int i) override;
  double compute_array(int i, int j) override;
  // fix_mbdyn_restart.cpp: the coupling's state, so a new LAMMPS process continues it with a peer
  // that continues it too (resume yes), or ignores it and starts a new coupling (resume no).
  void write_restart(FILE *fp) override;
  void restart(char *buf) override;

  // One pose of an MBDyn point in the global frame: position, orientation (row-major, local to
  // global), velocity and angular velocity.
  struct Pose {
    std::array<double, 3> x{}, v{}, w{};
    std::array<double, 9> R{1, 0, 0, 0, 1, 0, 0, 0, 1};
  };

 private:
  struct NodeSpec {
    bool is_atom = true;
    bool is_mesh = false;  // node mesh MESH-ID: drives mesh_driver (index into meshes_)
    bool is_vertex = false;  // mapping MESH-ID: a mapped point driving vertices of deform_ (is_mesh too)
    bool is_reference = false;  // `reference atom|group`: follows MBDyn's reference node (last slot)
    int mesh = -1;
    LAMMPS_NS::tagint tag = 0;
    std::string group;  // group ID, or the mesh fix ID
    int groupbit = 0;
    std::string text;  // "atom 17" or "group wall", for messages
  };
  struct Member {
    int node = -1;
    double r[3] = {0, 0, 0};  // body coordinates relative to the point, in the point's frame
  };
  // What rank 0 got from the socket, as every rank sees it after the broadcast.
  struct Message {
    int status = 0;  // 0 kinematics, 1 end of simulation (MBDyn sent 5), 2 error
    int command = 0;
    long long step = 0;
    int iteration = 0;
  };

  std::string where() const;
  std::string slot_name(std::size_t k) const;  // "node 3", or "reference" for the reference body
  [[noreturn]] void fail_all(const std::string &why);
  void check_atoms();
  void open_session();
  Message receive_broadcast(const char *expecting);
  const mbdyn::Kinematics &kinematics() const;  // the last message: the session's on rank 0
  void send_answer(const std::vector<double> &loads6, bool converged, const char *what);
  void decode_to_global(std::vector<Pose> &out);  // decode_poses, then check_poses
  void decode_poses(std::vector<Pose> &out);
  // fix_mbdyn_pose_check.cpp: an ERROR naming the node and the field for an orientation matrix
  // that is not a rotation or a pose that would put a coupled atom out of the box.
  void check_poses(const std::vector<Pose> &poses);
  void bind_atoms();
  void index_members();  // the per-step lookup tables from members_ (bind_atoms, restart)
  // fix_mbdyn_restart.cpp: after read_restart, the session continues MBDyn's step mbdyn_step_;
  // between sub-steps, the step's message is received again and must be the one restored.
  void resume_session();
  void check_restored_config();  // init: what the restart file's coupling needs of this command
  void interpolate(double s, std::vector<Pose> &out) const;
  void apply_pose(const std::vector<Pose> &poses, bool set_x);
  bool fast_member_lookup() const;
  // `node atom` couplings only (fix_mbdyn_node_atoms.cpp): the same results as apply_pose and
  // accumulate_loads' general path, with the atoms looked up and their rows prefetched first.
  bool node_atoms_fast_path() const;
  void find_node_atoms(int rows_for_write);
  void apply_pose_node_atoms(const std::vector<Pose> &poses, bool set_x);
  void accumulate_loads_node_atoms(const std::vector<Pose> &poses, std::vector<double> &local);
  void accumulate_loads(const std::vector<Pose> &poses, std::vector<double> &out6);
  void reevaluate_forces(int vflag);
  void stop_run_at_end(const Message &m);
  double pose_change(const std::vector<Pose> &a, const std::vector<Pose> &b) const;
  void correct_prediction(const std::vector<Pose> &msg);
  enum class PredictorEvidence { CrankNicolson, Other, Unknown };
  static PredictorEvidence follows_crank_nicolson(const std::vector<Pose> &prev, const std::vector<Pose> &msg, double T);
  bool pose_is_message() const;
  bool answer_is_global6() const;

  // configuration
  std::vector<NodeSpec> nodes_;  // MBDyn's points in the element's order, then the reference body if any
  std::size_t num_points_ = static_cast<std::size_t>(-1);  // MBDyn's points: nodes_ without the reference body
  std::unique_ptr<NodeSpec> reference_body_;              // as parsed (also the last entry of nodes_)
  bool use_reference_forces_ = true;     // MBDyn `use reference node forces`
  bool rotate_reference_forces_ = true;  // MBDyn `rotate reference node forces`
  bool reference_forces_given_ = false;
  bool sorted_ = true;
  std::unique_ptr<mbdyn::FileOptions> file_;  // file IN OUT (MBDyn's file communicator), else a socket
  double file_sleep_ = -1;                     // sleep S, if given
  int file_precision_ = -1;                    // precision P, if given  // MBDyn `sorted`: the answer is in the received order either way
  std::unique_ptr<mbdyn::SessionOptions> options_;
  int substeps_ = 1;
  double mbdyn_dt_ = -1.0;
  bool include_gravity_ = false;
  bool tight_ = false;
  bool extrapolate_ = false;  // loads extrapolate: sub-step average shifted to the end of the step
  bool correct_predictor_ = false;  // predictor correct: loads at a second-order end-of-step pose
  bool predictor_is_cn_ = true;     // predictor correct: MBDyn's predictions follow crank nicolson's so far
  bool warned_unverified_ = false;  // predictor correct: warned that no point tells the method
  bool startup_exchange_ = true;    // tight: the first message is the t0 (derivatives) exchange
  bool resume_ = true;              // read_restart: continue the restart file's coupling (resume yes)
  double tolerance_ = 1e-9;
  int max_iterations_ = 10;

  // rank 0 only
  std::unique_ptr<mbdyn::SocketListener> listener_;
  std::unique_ptr<mbdyn::PeerSession> session_;
  std::unique_ptr<mbdyn::FileSession> file_session_;  // file IN OUT: instead of session_

  // every rank
  std::vector<unsigned char> bcast_;         // header + raw payload, broadcast per message
  std::unique_ptr<mbdyn::Kinematics> kin_;  // ranks > 0: decoded from bcast_
  std::array<double, 9> ref_R_{1, 0, 0, 0, 1, 0, 0, 0, 1};
  std::array<double, 3> ref_x_{};
  bool bound_ = false;      // t0 exchanged, atoms bound to nodes
  bool ended_ = false;      // MBDyn sent 5
  bool failed_ = false;     // an error was raised: the destructor only aborts
  bool in_reeval_ = false;  // tight re-evaluation in progress
  int substep_ = 0;         // 0: the next step starts a new MBDyn step (receive)
  bool t0_answer_pending_ = false;
  bool restored_ = false;           // the state came from a restart file; the session is not open yet
  int restored_substeps_ = 0;       // substeps of the restart file's coupling (checked in init)
  std::vector<unsigned char> restored_payload_;  // between sub-steps: the step's message as received
  bool first_is_step1_ = false;     // tight, startup_exchange no: first message already received
  std::vector<Pose> prev_msg_;      // loose, predictor correct: the previous message as received
  std::vector<Pose> msg_;           // loose, predictor correct: this message as received
  // predictor correct with accelerations yes: per point a and omega_dot (6) of this message and
  // of the previous one (MBDyn's converged accelerations of the two steps before)
  std::vector<double> msg_acc_, prev_acc_;
  void read_accelerations(std::vector<double> &out) const;
  bool uses_accelerations() const;
  std::unordered_map<LAMMPS_NS::tagint, Member> members_;
  std::vector<std::pair<LAMMPS_NS::tagint, Member>> member_list_;  // members_ by tag
  bool one_atom_per_node_ = false;                                  // every node is `node atom`
  std::vector<LAMMPS_NS::tagint> node_tags_;  // one_atom_per_node_: member_list_'s tags,
  std::vector<int> node_index_;                // their nodes,
  std::vector<int> node_local_;                // their local indices (-1: not owned here), per use
  LAMMPS_NS::bigint node_local_build_ = -1;    // neighbor->ncalls when node_local_ was looked up
  int node_local_nlocal_ = -1;                 // and atom->nlocal then
  long long node_local_tags_ = -1, tags_version_ = 0;  // node_tags_ then and now (bind_atoms bumps it)
  std::vector<double> local_loads_, step_loads_, avg_;              // per-step buffers, reused
  std::unique_ptr<mbdyn::Loads> answer_;                            // the loads message, reused
  std::vector<MbdynMeshDriver> meshes_;  // node mesh entries, in order
  std::unique_ptr<MbdynDeformDriver> deform_;  // mapping MESH-ID: the mapped points drive its vertices
  std::string deform_mesh_;
  double match_tolerance_ = 1e-8;
  bool match_tolerance_given_ = false;
  std::vector<std::array<double, 3>> vertex_x_, vertex_v_;  // per mapped point, per move (reused)
  bool others_move_coupled_ = true;  // another fix may change coupled atoms' velocities (init)
  int allbits_ = 0;  // union of the group bits of coupled groups (0 if only atoms)
  std::vector<Pose> poseA_, poseB_, cur_;
  std::vector<double> node_radius_;  // per node: max |r| of its atoms (0 for node atom), from bind_atoms
  std::vector<double> fsum_;  // 6N sum of substep loads 1..N-1 of this MBDyn step
  std::vector<double> sent_;  // 6N last loads sent, global frame (unless answer_ holds them)
  std::vector<double> prev_avg_;  // 6N sub-step average of the previous MBDyn step (or t0 loads)
  bool prev_is_t0_ = true;
  long long mbdyn_step_ = 0;
  int last_iterations_ = 0;
  long long messages_ = 0;
  long long exchanges_ = 0;
  ExchangeProfile profile_;  // profile yes: the fix's own time per phase, logged after each run
};

}  // namespace dembridge
