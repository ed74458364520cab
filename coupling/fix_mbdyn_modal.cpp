// fix mbdyn ... modal (fix_mbdyn_modal.h). Every step: rank 0 reads MBDyn's kinematics and
// broadcasts them; every rank places its carried atoms (x, v); after the forces, the atoms'
// forces are summed per point over the ranks and rank 0 answers F, M, p.
#include "fix_mbdyn_modal.h"
#include "command_args.h"

#include "atom.h"
#include "comm.h"
#include "error.h"
#include "group.h"
#include "update.h"
#include "utils.h"

#include <mpi.h>

#include <algorithm>
#include <climits>
#include <cmath>
#include <cstring>
#include <exception>
#include <optional>

#include "protocol_error.h"
#include "socket_transport.h"
#include "tight_reevaluation.h"

using namespace LAMMPS_NS;
namespace mb = dembridge::mbdyn;

namespace dembridge {

namespace {
const char *kUsage = "fix mbdyn path FILE modal FEM-FILE [modes N [list m ...]] [origin LABEL] "
                     "[type all|rigid|modal] [match D] [mesh MESH-ID] [coupling loose|tight] [tolerance T] [max_iterations M] "
                     "[startup_exchange yes|no] [connect_timeout S] [io_timeout S] [resume yes|no]";
}

FixMBDynModal::FixMBDynModal(LAMMPS *lmp, int narg, char **arg) : Fix(lmp, narg, arg)
{
  if (narg < 7) error->all(FLERR, "Illegal fix mbdyn modal command: expected {}", kUsage);
  if (strcmp(arg[3], "path") != 0)
    error->all(FLERR, "fix mbdyn modal: expected 'path FILE' (a Unix socket) first, got '{}'", arg[3]);
  path_ = arg[4];
  if (strcmp(arg[5], "modal") != 0)
    error->all(FLERR, "fix mbdyn modal: expected 'modal FEM-FILE' after the socket, got '{}'", arg[5]);
  try {
    fem_ = mb::read_fem_file(arg[6]);
  } catch (const std::exception &e) {
    error->all(FLERR, "fix mbdyn modal: {}", e.what());
  }
  std::size_t modes = fem_.num_modes;
  std::vector<int> list;
  std::string tight_keyword;  // the last keyword given that only tight coupling reads
  for (int i = 7; i < narg; ++i) {
    const std::string k = arg[i];
    auto value = [&](const char *what) -> const char * {
      if (i + 1 >= narg) error->all(FLERR, "fix mbdyn modal: expected {} after '{}'", what, k);
      return arg[++i];
    };
    auto number_of = [&](const char *kw, const std::string &w, const char *expected) {
      const std::optional<double> v = args::number(lmp, w);
      if (!v) error->all(FLERR, "fix mbdyn modal: {}: expected {} (a finite number), got '{}'", kw, expected, w);
      return *v;
    };
    if (k == "modes") {
      const std::string w = value("the number of modes of the modal joint");
      const std::optional<long long> n = args::integer(lmp, w);
      if (!n || *n > INT_MAX) error->all(FLERR, "fix mbdyn modal: modes: expected an integer >= 1, got '{}'", w);
      if (*n < 1) error->all(FLERR, "fix mbdyn modal: expected modes >= 1, got {}", *n);
      modes = std::size_t(*n);
      if (i + 1 < narg && strcmp(arg[i + 1], "list") == 0) {
        ++i;
        for (long long m = 0; m < *n; ++m) {
          const std::string mode = value("a mode number");
          const std::optional<long long> v = args::integer(lmp, mode);
          if (!v || *v > INT_MAX || *v < INT_MIN)
            error->all(FLERR, "fix mbdyn modal: modes list: expected a mode number (an integer), got '{}'", mode);
          list.push_back(int(*v));
        }
      }
    } else if (k == "origin") {
      origin_ = value("a FEM node label");
    } else if (k == "type") {
      try {
        config_.type = mb::modal_type_from_name(value("all, rigid or modal"));
      } catch (const std::exception &e) {
        error->all(FLERR, "fix mbdyn modal: {}", e.what());
      }
    } else if (k == "match") {
      match_ = number_of("match", value("a distance"), "a distance >= 0");
      if (!(match_ >= 0)) error->all(FLERR, "fix mbdyn modal: expected match >= 0, got {}", match_);
    } else if (k == "mesh") {
      mesh_id_ = value("the ID of a fix mesh/surface/stress");
    } else if (k == "coupling") {
      const std::string c = value("loose or tight");
      if (c != "loose" && c != "tight")
        error->all(FLERR, "fix mbdyn modal: coupling: expected loose or tight, got '{}'", c);
      tight_ = c == "tight";
    } else if (k == "tolerance") {
      tolerance_ = number_of("tolerance", value("a kinematics change"), "a kinematics change >= 0");
      if (!(tolerance_ >= 0)) error->all(FLERR, "fix mbdyn modal: expected tolerance >= 0, got {}", tolerance_);
      tight_keyword = k;
    } else if (k == "max_iterations") {
      const std::string w = value("the most exchanges per MBDyn step");
      const std::optional<long long> n = args::integer(lmp, w);
      if (!n || *n < 1 || *n > INT_MAX)
        error->all(FLERR, "fix mbdyn modal: max_iterations: expected an integer >= 1, got '{}'", w);
      max_iterations_ = int(*n);
      tight_keyword = k;
    } else if (k == "startup_exchange") {
      const std::string w = value("yes or no");
      if (w != "yes" && w != "no")
        error->all(FLERR, "fix mbdyn modal: startup_exchange: expected yes or no, got '{}'", w);
      startup_exchange_ = w == "yes";
      tight_keyword = k;
    } else if (k == "resume") {
      const std::string w = value("yes or no");
      if (w != "yes" && w != "no") error->all(FLERR, "fix mbdyn modal: resume: expected yes or no, got '{}'", w);
      resume_ = w == "yes";
    } else if (k == "connect_timeout") {
      connect_timeout_ = number_of("connect_timeout", value("seconds"), "seconds");
    } else if (k == "io_timeout") {
      io_timeout_ = number_of("io_timeout", value("seconds"), "seconds");
    } else {
      error->all(FLERR, "fix mbdyn modal: unknown keyword '{}', expected {}", k, kUsage);
    }
  }
  if (!tight_ && !tight_keyword.empty())
    error->all(FLERR, "fix mbdyn modal: '{}' is for coupling tight (loose coupling answers each message once)",
               tight_keyword);
  try {
    fem_ = mb::select_modes(fem_, modes, list);
    if (!origin_.empty()) fem_.node_index(origin_);
  } catch (const std::exception &e) {
    error->all(FLERR, "fix mbdyn modal: {}", e.what());
  }
  config_.num_modes = static_cast<std::uint32_t>(modes);
  vector_flag = 1;
  size_vector = 6 + static_cast<int>(modes);
  extvector = 0;
  global_freq = 1;
  restart_global = 1;
  kin_.q.assign(modes, 0.0);
  kin_.qdot.assign(modes, 0.0);
  last_.p.assign(modes, 0.0);
}

FixMBDynModal::~FixMBDynModal() { stop_peer(); }

// Leaves MBDyn in a clean state, as fix mbdyn does: its next message (a step LAMMPS will not
// run) is answered with 5, so it ends as asked by its peer. Bounded by io_timeout; nothing after an error.
void FixMBDynModal::stop_peer()
{
  if (comm->me != 0 || !transport_ || ended_ || failed_) return;
  try {
    if (!first_is_step1_) {  // else that message was received and is not answered yet
      std::uint8_t c = 0;
      transport_->read_exact(&c, 1, io_timeout_, "MBDyn's next command");
      if (c == 5) return;
      std::vector<unsigned char> payload(config_.kinematics_payload_bytes());
      transport_->read_exact(payload.data(), payload.size(), io_timeout_, "MBDyn's next kinematics");
    }
    const std::uint8_t five = 5;
    transport_->write_all(&five, 1, io_timeout_, "the end of the coupling (5)");
  } catch (const std::exception &) {
  }
}

// PRE_EXCHANGE only for setup_pre_exchange: the t0 pose is set before the set-up's forces
int FixMBDynModal::setmask() { return FixConst::PRE_EXCHANGE | FixConst::POST_INTEGRATE | FixConst::POST_FORCE; }

void FixMBDynModal::fail(const std::string &why)
{
  failed_ = true;
  error->all(FLERR, "fix mbdyn modal: {}", why);
}

// Only rank 0 talks to MBDyn: its error text (empty: none) reaches every rank, which all stop.
void FixMBDynModal::fail_if_rank0_failed(std::string err)
{
  int n = static_cast<int>(err.size());
  MPI_Bcast(&n, 1, MPI_INT, 0, world);
  if (n == 0) return;
  err.resize(n);
  MPI_Bcast(&err[0], n, MPI_CHAR, 0, world);
  fail(err);
}

void FixMBDynModal::init()
{
  if (!mesh_id_.empty()) {  // the mesh is carried instead of the group's atoms
    if (!deform_) {
      deform_ = std::make_unique<MbdynDeformDriver>();
      deform_->attach(lmp, mesh_id_, "fix mbdyn modal: mesh " + mesh_id_);
    }
    return;
  }
  if (group->count(igroup) == 0) fail("group '" + std::string(group->names[igroup]) + "' has no atoms to carry");
}

// Rank 0 reads one message (or MBDyn's 5) and broadcasts it; an error on rank 0 reaches all.
bool FixMBDynModal::receive()
{
  std::string err;
  int cmd = 0;
  const std::size_t n = config_.kinematics_payload_bytes();
  buf_.assign(n, 0);
  if (comm->me == 0) {
    try {
      if (!connected_) {
        transport_ = std::make_unique<mb::SocketTransport>(
            mb::SocketTransport::connect(mb::Endpoint::unix_path(path_), connect_timeout_));
        const auto request = mb::modal_negotiation_request_bytes(config_);
        transport_->write_all(request.data(), request.size(), io_timeout_, "the negotiation request");
        std::uint8_t ok = 0;
        transport_->read_exact(&ok, 1, io_timeout_, "the negotiation answer (8 = ok)");
        if (ok != static_cast<std::uint8_t>(mb::Command::Ok))
          throw mb::NegotiationError("MBDyn refused the negotiation (answer " + mb::command_name(ok) + ") for " +
                                     config_.describe() + "; check `type` and the modal joint's mode count");
      }
      std::uint8_t c = 0;
      const int data_cmd = tight_ ? 2 : 6;
      transport_->read_exact(&c, 1, io_timeout_, tight_ ? "a kinematics command (2 or 5)" : "a kinematics command (6 or 5)");
      cmd = c;
      if (cmd == data_cmd) {
        transport_->read_exact(buf_.data(), n, io_timeout_, "the external modal kinematics");
      } else if (cmd != 5) {
        const char *hint = cmd == 2 ? "; MBDyn's coupling is tight, this fix is loose (coupling tight)"
                           : cmd == 6 ? "; MBDyn's coupling is loose, this fix is tight (coupling loose)" : "";
        throw mb::MalformedMessageError(std::string("expected command ") + (tight_ ? "2 (tight" : "6 (loose") +
                                        " kinematics) or 5 (end) from MBDyn, received " + mb::command_name(c) + hint);
      }
    } catch (const std::exception &e) {
      err = e.what();
      if (err.empty()) err = "unknown error";
    }
  }
  connected_ = true;
  fail_if_rank0_failed(err);
  MPI_Bcast(&cmd, 1, MPI_INT, 0, world);
  if (cmd == 5) return false;
  MPI_Bcast(buf_.data(), static_cast<int>(n), MPI_BYTE, 0, world);
  try {
    kin_ = mb::decode_modal_kinematics(
        config_, tight_ ? mb::Command::RegularData : mb::Command::RegularDataAndGotoNextStep, buf_.data(), n);
  } catch (const std::exception &e) {
    fail(e.what());
  }
  if (!config_.has_modes()) {
    kin_.q.assign(config_.num_modes, 0.0);
    kin_.qdot.assign(config_.num_modes, 0.0);
  }
  ++messages_;
  return true;
}

// The carried atoms, in tag order, each put on the FEM node at its position: the position given
// in the FEM frame of the first message's pose (type modal: the global frame, modal node at 0).
void FixMBDynModal::bind_atoms()
{
  if (deform_) {  // every FEM node is a point, in node order (points are FEM frame positions)
    body_ = mb::map_points_to_fem_nodes(fem_, fem_.node_xyz, origin_, 0.0);
    bound_ = true;
    return;
  }
  const int nlocal = atom->nlocal;
  std::vector<double> mine;  // tag, x, y, z
  for (int i = 0; i < nlocal; ++i)
    if (atom->mask[i] & groupbit) {
      mine.push_back(static_cast<double>(atom->tag[i]));
      for (int c = 0; c < 3; ++c) mine.push_back(atom->x[i][c]);
    }
  int count = static_cast<int>(mine.size());
  std::vector<int> counts(comm->nprocs), displs(comm->nprocs, 0);
  MPI_Allgather(&count, 1, MPI_INT, counts.data(), 1, MPI_INT, world);
  for (int r = 1; r < comm->nprocs; ++r) displs[r] = displs[r - 1] + counts[r - 1];
  std::vector<double> all(displs.back() + counts.back());
  MPI_Allgatherv(mine.data(), count, MPI_DOUBLE, all.data(), counts.data(), displs.data(), MPI_DOUBLE, world);
  std::vector<std::size_t> order(all.size() / 4);
  for (std::size_t k = 0; k < order.size(); ++k) order[k] = k;
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return all[4 * a] < all[4 * b]; });
  std::array<double, 3> origin{0, 0, 0};
  if (!origin_.empty()) origin = fem_.node_xyz[fem_.node_index(origin_)];
  std::vector<std::array<double, 3>> points;
  tags_.clear();
  point_of_.clear();
  for (std::size_t k : order) {
    const double d[3] = {all[4 * k + 1] - kin_.x[0], all[4 * k + 2] - kin_.x[1], all[4 * k + 3] - kin_.x[2]};
    const auto &R = kin_.R;  // FEM frame position = R^T (x - x_n) + origin
    points.push_back({R[0] * d[0] + R[3] * d[1] + R[6] * d[2] + origin[0],
                      R[1] * d[0] + R[4] * d[1] + R[7] * d[2] + origin[1],
                      R[2] * d[0] + R[5] * d[1] + R[8] * d[2] + origin[2]});
    const auto tag = static_cast<tagint>(all[4 * k]);
    point_of_[tag] = tags_.size();
    tags_.push_back(tag);
  }
  try {
    body_ = mb::map_points_to_fem_nodes(fem_, points, origin_, match_);
  } catch (const std::exception &e) {
    std::string why = e.what();
    const auto at = why.find("point ");
    if (at == 0) {  // name the atom, not the point index
      const std::size_t p = std::stoul(why.substr(6)) - 1;
      why = "atom " + std::to_string(tags_[p]) + why.substr(why.find(' ', 6));
    }
    fail(why + " (atoms must sit on FEM nodes; see 'match')");
  }
  if (first_is_step1_) {
    // The pose they were matched at is step 1's prediction, not the atoms' t0 pose: each atom is
    // carried from its FEM node, not from where it was matched.
    std::array<double, 3> origin_xyz{0, 0, 0};
    if (!origin_.empty()) origin_xyz = fem_.node_xyz[fem_.node_index(origin_)];
    for (std::size_t p = 0; p < body_.rest.size(); ++p)
      for (int c = 0; c < 3; ++c) body_.rest[p][c] = fem_.node_xyz[body_.fem_node[p]][c] - origin_xyz[c];
  }
  bound_ = true;
}

void FixMBDynModal::place_atoms()
{
  try {
    mb::modal_point_states(body_, kin_, x_, v_);
  } catch (const std::exception &e) {
    fail(e.what());
  }
  if (deform_) {
    std::vector<MbdynDeformDriver::V3> xs(x_.size() / 3), vs(x_.size() / 3);
    for (std::size_t p = 0; p < xs.size(); ++p)
      for (int c = 0; c < 3; ++c) {
        xs[p][c] = x_[3 * p + c];
        vs[p][c] = v_[3 * p + c];
      }
    if (!mesh_bound_) {
      const std::string why = deform_->bind(xs, match_);
      if (!why.empty())
        fail("mesh " + mesh_id_ + ": " + why + " (match " + std::to_string(match_) +
             "; each vertex of the mesh as placed must be at one FEM node of the first message's pose; point n is the "
             "n-th node of the FEM file)");
      mesh_bound_ = true;
    }
    deform_->move_to(xs, vs);
    return;
  }
  for (int i = 0; i < atom->nlocal; ++i) {
    if (!(atom->mask[i] & groupbit)) continue;
    const auto it = point_of_.find(atom->tag[i]);
    if (it == point_of_.end()) fail("atom " + std::to_string(atom->tag[i]) + " joined the group after the run's set-up");
    for (int c = 0; c < 3; ++c) {
      atom->x[i][c] = x_[3 * it->second + c];
      atom->v[i][c] = v_[3 * it->second + c];
    }
  }
}

void FixMBDynModal::answer(bool converged)
{
  std::vector<double> f;
  if (deform_) {  // the wall contacts split to the vertices (the FEM nodes), summed in a rank-free order
    const std::size_t n = fem_.num_nodes();
    std::vector<double> out6(6 * n, 0.0);
    deform_->loads(out6.data());
    f.resize(3 * n);
    for (std::size_t p = 0; p < n; ++p)
      for (int c = 0; c < 3; ++c) f[3 * p + c] = out6[6 * p + c];
  } else {
    std::vector<double> local(3 * tags_.size(), 0.0);
    f.assign(3 * tags_.size(), 0.0);
    for (int i = 0; i < atom->nlocal; ++i) {
      if (!(atom->mask[i] & groupbit)) continue;
      const std::size_t p = point_of_.at(atom->tag[i]);
      for (int c = 0; c < 3; ++c) local[3 * p + c] += atom->f[i][c];
    }
    MPI_Allreduce(local.data(), f.data(), static_cast<int>(f.size()), MPI_DOUBLE, MPI_SUM, world);
  }
  try {
    last_ = mb::project_modal_loads(body_, kin_, x_, f);
  } catch (const std::exception &e) {
    fail(e.what());
  }
  std::string err;
  if (comm->me == 0) {
    try {
      const auto bytes = mb::encode_modal_loads(
          config_, converged ? mb::Command::RegularDataAndGotoNextStep : mb::Command::RegularData, last_);
      transport_->write_all(bytes.data(), bytes.size(), io_timeout_, "the external modal loads");
    } catch (const std::exception &e) {
      err = e.what();
    }
  }
  fail_if_rank0_failed(err);
}

void FixMBDynModal::setup_pre_exchange()
{
  if (restored_) resume_coupling();  // the first run after read_restart
  if (bound_ || ended_) return;
  if (!config_.has_rigid()) bind_atoms();  // the pose is the FEM frame: map before connecting
  if (!receive()) {
    ended_ = true;
    return;
  }
  // Tight without the start-up exchange: MBDyn's initial derivatives did not iterate, so this
  // first message is already step 1's prediction, answered by the first step as an iterate.
  first_is_step1_ = tight_ && !startup_exchange_;
  if (!bound_) bind_atoms();
  place_atoms();
}

void FixMBDynModal::setup(int)
{
  if (ended_ || t0_answered_ || messages_ != 1 || first_is_step1_) return;
  answer(true);  // the t0 exchange feeds MBDyn's initial derivatives (6 also in tight coupling)
  t0_answered_ = true;
}

// The largest change of any value of the message (x, R, v, omega, q, qdot) from a to b.
double FixMBDynModal::kinematics_change(const mb::ModalKinematics &a, const mb::ModalKinematics &b)
{
  double d = 0;
  auto take = [&d](const double *p, const double *q, std::size_t n) {
    for (std::size_t i = 0; i < n; ++i) d = std::max(d, std::fabs(p[i] - q[i]));
  };
  take(a.x.data(), b.x.data(), 3);
  take(a.R.data(), b.R.data(), 9);
  take(a.v.data(), b.v.data(), 3);
  take(a.omega.data(), b.omega.data(), 3);
  take(a.q.data(), b.q.data(), std::min(a.q.size(), b.q.size()));
  take(a.qdot.data(), b.qdot.data(), std::min(a.qdot.size(), b.qdot.size()));
  return d;
}

// MBDyn's iterates of one step: each is answered with 2 until two consecutive ones differ by at
// most `tolerance` in every value (or at the max_iterations-th exchange), which is answered 6.
void FixMBDynModal::iterate_tight(int vflag)
{
  for (int it = 0;; ++it) {
    const int converged = it + 1 >= max_iterations_ || (it > 0 && last_change_ <= tolerance_);
    answer(converged != 0);  // every rank holds the same kinematics: the same decision
    if (converged) return;
    const mb::ModalKinematics before = kin_;
    if (!receive()) {
      ended_ = true;
      if (comm->me == 0)
        error->warning(FLERR, "fix mbdyn modal: MBDyn ended the simulation within a step; the carried atoms stay where they are");
      return;
    }
    last_change_ = kinematics_change(before, kin_);
    place_atoms();
    reevaluate_forces_for_iterate(lmp, id, vflag, [this]() {
      if (deform_) deform_->restart_totals();
    });
  }
}

void FixMBDynModal::post_integrate()
{
  if (ended_) return;
  if (first_is_step1_) {  // the message received at the set-up is this step's prediction
    first_is_step1_ = false;
    place_atoms();
    return;
  }
  if (!receive()) {
    ended_ = true;
    if (comm->me == 0) error->warning(FLERR, "fix mbdyn modal: MBDyn ended the simulation; the carried atoms stay where they are");
    return;
  }
  place_atoms();
}

void FixMBDynModal::post_force(int vflag)
{
  if (ended_ || update->setupflag != 0) return;
  if (!tight_) {
    answer(true);
    return;
  }
  iterate_tight(vflag);
}

double FixMBDynModal::compute_vector(int i)
{
  if (i < 3) return last_.force[i];
  if (i < 6) return last_.moment[i - 3];
  return last_.p[i - 6];
}

}  // namespace dembridge
