// fix mbdyn's restart record: the state a new LAMMPS process needs to continue the coupling
// where write_restart left it, bit for bit, with a peer that continues the same coupling
// (doc/fix_mbdyn.md, "Restart info"). The atoms, the mesh vertices (fix mesh/surface) and the
// wall history (fix wall/gran) carry their own state; this record holds the MBDyn poses of the
// step and the sub-step interpolation, the load sums, the binding of the atoms to the points and,
// between sub-steps, the step's message as received.
#include "fix_mbdyn.h"

#include "comm.h"
#include "error.h"

#include "file_session.h"
#include "nodal_config.h"
#include "peer_session.h"
#include "restart_doubles.h"

#include <mpi.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <exception>

using namespace LAMMPS_NS;

namespace dembridge {

namespace {

constexpr double kMagic = 25052026.0;  // marks fix mbdyn's record
constexpr double kVersion = 1.0;
constexpr double kModalMagic = 25122026.0;  // fix mbdyn ... modal's record (fix_mbdyn_modal_restart.cpp)

// What each point is, as the restart file records it (compared with the command's entries).
int kind_of(bool is_atom, bool is_mesh, bool is_vertex, bool is_reference)
{
  if (is_vertex) return 3;
  if (is_mesh) return 2;
  return (is_reference ? 10 : 0) + (is_atom ? 0 : 1);
}

const char *kind_name(int kind)
{
  switch (kind) {
    case 0: return "an 'atom' entry";
    case 1: return "a 'group' entry";
    case 2: return "a 'mesh' entry";
    case 3: return "a mapped point";
    case 10: return "a 'reference atom' entry";
    case 11: return "a 'reference group' entry";
  }
  return "an unknown entry";
}

// The generic record with fix mbdyn's poses.
class Record : public RestartDoubles {
 public:
  using RestartDoubles::RestartDoubles;
  using RestartDoubles::get;
  using RestartDoubles::put;
  void put_pose(const FixMBDyn::Pose &p)
  {
    put(p.x.data(), 3);
    put(p.v.data(), 3);
    put(p.w.data(), 3);
    put(p.R.data(), 9);
  }
  void get_pose(FixMBDyn::Pose &p)
  {
    get(p.x.data(), 3);
    get(p.v.data(), 3);
    get(p.w.data(), 3);
    get(p.R.data(), 9);
  }
};

}  // namespace

void FixMBDyn::write_restart(FILE *fp)
{
  std::vector<double> buf;
  Record r(buf);
  r.put(0.0);  // the count of doubles, set at the end
  r.put(kMagic);
  r.put(kVersion);
  r.put(static_cast<double>(num_points_));
  r.put(static_cast<double>(nodes_.size()));
  r.put(static_cast<double>(options_->nodal.kinematics_payload_bytes()));
  r.put(tight_ ? 1 : 0);
  r.put(file_ ? 1 : 0);
  for (const NodeSpec &n : nodes_) {
    r.put(kind_of(n.is_atom, n.is_mesh, n.is_vertex, n.is_reference));
    r.put(n.is_atom ? static_cast<double>(n.tag) : 0.0);
  }
  r.put_text(deform_mesh_);
  r.put(bound_);
  r.put(ended_);
  r.put(substeps_);
  r.put(substep_);
  r.put(t0_answer_pending_);
  r.put(first_is_step1_);
  r.put(prev_is_t0_);
  r.put(predictor_is_cn_);
  r.put(warned_unverified_);
  r.put(static_cast<double>(mbdyn_step_));
  r.put(last_iterations_);
  r.put(static_cast<double>(messages_));
  r.put(static_cast<double>(exchanges_));
  r.put(ref_R_.data(), 9);
  r.put(ref_x_.data(), 3);
  for (const std::vector<Pose> *poses : {&poseA_, &poseB_, &cur_})
    for (const Pose &p : *poses) r.put_pose(p);
  r.put(static_cast<double>(prev_msg_.size()));
  for (const Pose &p : prev_msg_) r.put_pose(p);
  r.put_vector(prev_acc_);
  r.put_vector(fsum_);
  r.put_vector(prev_avg_);
  std::vector<double> sent = sent_;  // the last loads sent, as compute_array gives them
  for (std::size_t i = 0; answer_is_global6() && answer_ && i < nodes_.size(); ++i)
    for (int j = 0; j < 6; ++j) sent[6 * i + j] = compute_array(static_cast<int>(i), j);
  r.put_vector(sent);
  r.put(static_cast<double>(member_list_.size()));
  for (const auto &tm : member_list_) {
    r.put(static_cast<double>(tm.first));
    r.put(tm.second.node);
    r.put(tm.second.r, 3);
  }
  if (comm->me != 0) return;  // rank 0 writes; it alone holds the message bytes
  // Between sub-steps the step's message is received again after the restart: its bytes, to
  // check that the peer continues the same coupling.
  std::vector<unsigned char> payload;
  if (bound_ && !ended_ && substep_ > 0 && (session_ || file_session_))
    payload = session_ ? session_->raw_payload() : file_session_->raw_payload();
  r.put(static_cast<double>(payload.size()));
  std::vector<double> packed((payload.size() + sizeof(double) - 1) / sizeof(double), 0.0);
  if (!payload.empty()) std::memcpy(packed.data(), payload.data(), payload.size());
  r.put(packed.data(), packed.size());

  buf[0] = static_cast<double>(buf.size());
  const int size = static_cast<int>(buf.size() * sizeof(double));
  std::fwrite(&size, sizeof(int), 1, fp);
  std::fwrite(buf.data(), sizeof(double), buf.size(), fp);
}

void FixMBDyn::restart(char *raw)
{
  const std::string prefix = where() + ": read_restart: ";
  // LAMMPS hands the record without its length: its first double is the count of doubles.
  double first[8];
  std::memcpy(first, raw, sizeof(first));
  if (first[1] == kModalMagic)
    error->all(FLERR, prefix + "the restart file's record of this fix ID was written by fix mbdyn ... modal; this "
                               "command has no 'modal FEM-FILE'");
  if (first[1] != kMagic || first[2] != kVersion || !(first[0] >= 8 && first[0] < 1e12))
    error->all(FLERR, prefix + "the restart file's record of this fix ID is not one of this fix mbdyn version");
  std::vector<double> in(static_cast<std::size_t>(first[0]));
  std::memcpy(in.data(), raw, in.size() * sizeof(double));
  const double *head = in.data() + 1;
  if (!resume_) {
    if (comm->me == 0)
      error->warning(FLERR, where() + ": resume no: the coupling state of the restart file is ignored; this run "
                                      "starts a new coupling with MBDyn's start-up (t0) message");
    return;
  }
  const std::size_t npoints = static_cast<std::size_t>(head[2]), nslots = static_cast<std::size_t>(head[3]);
  Record r(in.data(), in.size());
  for (int i = 0; i < 8; ++i) r.get();  // the count and the header
  auto refuse = [&](const std::string &why) {
    error->all(FLERR, prefix + why + " (the command after read_restart must describe the coupling of the run that "
                               "wrote the restart file; 'resume no' starts a new coupling instead)");
  };
  if (npoints != num_points_) {
    const std::string what = deform_ ? "mapped points ('mapping " + deform_mesh_ + " points M')" : "MBDyn points ('node' entries)";
    refuse("the restart file's coupling has " + std::to_string(npoints) + " " + what + ", this command " +
           std::to_string(num_points_));
  }
  if (nslots != nodes_.size())
    refuse(std::string("the restart file's coupling ") + (nslots > npoints ? "has" : "has no") +
           " 'reference atom|group' body, this command " + (reference_body_ ? "has one" : "none"));
  if (static_cast<std::size_t>(head[4]) != options_->nodal.kinematics_payload_bytes())
    refuse("the restart file's kinematics messages have " + std::to_string(static_cast<long long>(head[4])) +
           " bytes, this command's " + std::to_string(options_->nodal.kinematics_payload_bytes()) + " (" +
           options_->nodal.describe() + "): 'orientation', 'labels', 'accelerations' or 'reference_node' differ");
  if ((head[5] != 0) != tight_)
    refuse(std::string("the restart file's coupling is ") + (head[5] != 0 ? "tight" : "loose") + ", this command's " +
           (tight_ ? "tight" : "loose") + " ('coupling')");
  if (head[6] != 0 || file_)
    refuse("a coupling over 'file IN OUT' cannot be continued: MBDyn's file communicator has no way to resume");
  for (std::size_t k = 0; k < nslots; ++k) {
    const int kind = static_cast<int>(r.get_int());
    const long long tag = r.get_int();
    const NodeSpec &n = nodes_[k];
    const int mine = kind_of(n.is_atom, n.is_mesh, n.is_vertex, n.is_reference);
    if (kind != mine)
      refuse(slot_name(k) + " is " + kind_name(mine) + " ('" + n.text + "') here, but was " + kind_name(kind) +
             " when the restart file was written");
    if (n.is_atom && tag != static_cast<long long>(n.tag))
      refuse(slot_name(k) + " is 'atom " + std::to_string(n.tag) + "' here, but was 'atom " + std::to_string(tag) +
             "' when the restart file was written");
  }
  const std::string mesh = r.get_text();
  if (mesh != deform_mesh_)
    refuse("the restart file's mapped points drive mesh '" + mesh + "', this command's mesh '" + deform_mesh_ + "'");
  if (r.get() == 0.0) return;  // written before the coupling started: a new one starts here
  bound_ = true;
  ended_ = r.get() != 0.0;
  restored_substeps_ = static_cast<int>(r.get_int());
  substep_ = static_cast<int>(r.get_int());
  t0_answer_pending_ = r.get() != 0.0;
  first_is_step1_ = r.get() != 0.0;
  prev_is_t0_ = r.get() != 0.0;
  predictor_is_cn_ = r.get() != 0.0;
  warned_unverified_ = r.get() != 0.0;
  mbdyn_step_ = r.get_int();
  last_iterations_ = static_cast<int>(r.get_int());
  messages_ = r.get_int();
  exchanges_ = r.get_int();
  r.get(ref_R_.data(), 9);
  r.get(ref_x_.data(), 3);
  for (std::vector<Pose> *poses : {&poseA_, &poseB_, &cur_})
    for (Pose &p : *poses) r.get_pose(p);
  prev_msg_.resize(static_cast<std::size_t>(r.get_int()));
  for (Pose &p : prev_msg_) r.get_pose(p);
  r.get_vector(prev_acc_);
  r.get_vector(fsum_);
  r.get_vector(prev_avg_);
  r.get_vector(sent_);
  members_.clear();
  const long long nmembers = r.get_int();
  for (long long j = 0; j < nmembers && r.ok(); ++j) {
    const tagint tag = static_cast<tagint>(r.get_int());
    Member m;
    m.node = static_cast<int>(r.get_int());
    r.get(m.r, 3);
    members_.emplace(tag, m);
  }
  const long long nbytes = r.get_int();
  restored_payload_.assign(static_cast<std::size_t>(nbytes > 0 ? nbytes : 0), 0);
  std::vector<double> packed((restored_payload_.size() + sizeof(double) - 1) / sizeof(double));
  r.get(packed.data(), packed.size());
  if (!restored_payload_.empty()) std::memcpy(restored_payload_.data(), packed.data(), restored_payload_.size());
  if (!r.ok() || fsum_.size() != 6 * nslots || sent_.size() != 6 * nslots)
    refuse("the restart file's record of this fix is truncated or damaged");
  index_members();
  restored_ = true;
}

void FixMBDyn::check_restored_config()
{
  if (!restored_ || restored_substeps_ == substeps_) return;
  error->all(FLERR, where() + ": read_restart: the restart file's coupling has " + std::to_string(restored_substeps_) +
                        " LAMMPS steps per MBDyn step, this command and timestep " + std::to_string(substeps_) +
                        " ('substeps' or 'mbdyn_dt' and the timestep must be those of the run that wrote the restart "
                        "file; 'resume no' starts a new coupling instead)");
}

void FixMBDyn::resume_session()
{
  restored_ = false;
  if (ended_) return;  // MBDyn had ended the simulation: nothing to continue
  open_session();
  // The next message is MBDyn's step after the last one answered; between sub-steps that is the
  // step whose message this process already holds, sent again.
  const long long answered = substep_ > 0 ? mbdyn_step_ - 1 : mbdyn_step_;
  if (comm->me == 0) session_->continue_after_step(static_cast<std::uint64_t>(answered));
  for (std::size_t k = 0; k < nodes_.size(); ++k)
    if (nodes_[k].is_mesh && !nodes_[k].is_vertex) meshes_[nodes_[k].mesh].bind(cur_[k].x, cur_[k].R);
  if (deform_) {
    // the mesh as restored by its fix has every vertex at its point of the last pose
    vertex_x_.resize(num_points_);
    for (std::size_t k = 0; k < num_points_; ++k) vertex_x_[k] = cur_[k].x;
    const std::string why = deform_->bind(vertex_x_, match_tolerance_);
    if (!why.empty())
      fail_all("read_restart: mapping " + deform_mesh_ + " points " + std::to_string(num_points_) + ": " + why +
               " (the mesh of the restart file is not at the restart file's mapped points: define the mesh with the "
               "same file and options as the run that wrote it)");
  }
  if (substep_ == 0) return;
  const Message m = receive_broadcast("MBDyn's kinematics of its current step again (restart between sub-steps)");
  if (m.status == 1)
    fail_all("read_restart: MBDyn ended the simulation instead of sending its step " + std::to_string(mbdyn_step_) +
             " again (the restart file was written between sub-steps of that step)");
  --messages_;  // the same message as before the restart
  int same = 1;
  if (comm->me == 0) same = session_->raw_payload() == restored_payload_;
  MPI_Bcast(&same, 1, MPI_INT, 0, world);
  if (!same)
    fail_all("read_restart: MBDyn's message of step " + std::to_string(mbdyn_step_) + " is not the one received "
             "before write_restart (the restart file was written between sub-steps of that step): the peer does not "
             "continue the same coupling; restart it from its state at the end of step " + std::to_string(answered) +
             ", or use 'resume no' with a peer that starts anew");
}

}  // namespace dembridge
