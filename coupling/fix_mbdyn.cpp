// fix mbdyn: see fix_mbdyn.h and doc/fix_mbdyn.md.
#include "fix_mbdyn.h"
#include "command_args.h"
#include "lammps_compat.h"
#include "fix_mbdyn_modal.h"

#include "atom.h"
#include "bond.h"
#include "comm.h"
#include "domain.h"
#include "error.h"
#include "force.h"
#include "group.h"
#include "modify.h"
#include "pair.h"
#include "timer.h"
#include "update.h"
#include "utils.h"

#include "math/rotation.h"
#include "file_session.h"
#include "peer_session.h"
#include "protocol_error.h"
#include "style_registry.h"
#include "tight_reevaluation.h"

#include <mpi.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <exception>
#include <limits>
#include <optional>
#include <sstream>

using namespace LAMMPS_NS;
using namespace LAMMPS_NS::FixConst;
namespace mb = dembridge::mbdyn;

namespace dembridge {

namespace {

using M9 = std::array<double, 9>;
using V3 = std::array<double, 3>;

using math::cross;  // the math layer (math/rotation.h): MBDyn's row-major orientations
using math::mat_mul;
using math::mat_t_vec;
using math::mat_vec;
using math::slerp;

bool parse_yes_no(const std::string &kw, const std::string &v, const std::string &prefix, Error *error)
{
  if (v == "yes") return true;
  if (v == "no") return false;
  error->all(FLERR, prefix + "keyword '" + kw + "' expects yes or no, got '" + v + "'");
}

double parse_double(LAMMPS *lmp, const std::string &kw, const std::string &v, const std::string &prefix,
                    const char *expected)
{
  const std::optional<double> d = args::number(lmp, v);
  if (!d) lmp->error->all(FLERR, prefix + "keyword '" + kw + "' expects " + expected + ", got '" + v + "'");
  return *d;
}

long long parse_int(LAMMPS *lmp, const std::string &kw, const std::string &v, const std::string &prefix,
                    const char *expected, long long lo)
{
  const std::optional<long long> d = args::integer(lmp, v);
  if (!d || *d < lo) lmp->error->all(FLERR, prefix + "keyword '" + kw + "' expects " + expected + ", got '" + v + "'");
  return *d;
}

std::string num(double v)
{
  char buf[32];
  std::snprintf(buf, sizeof(buf), "%g", v);
  return buf;
}

const char *kKeywords =
    "path, port, host, file, sleep, precision, create, coupling, orientation, labels, sorted, accelerations, reference_node, "
    "reference_forces, rotate_reference_forces, reference, node, mapping, match_tolerance, "
    "substeps, mbdyn_dt, loads, predictor, startup_exchange, gravity, connect_timeout, io_timeout, tolerance, "
    "max_iterations, profile, resume";

}  // namespace

FixMBDyn::FixMBDyn(LAMMPS *lmp, int narg, char **arg) :
    Fix(lmp, narg, arg), options_(std::make_unique<mb::SessionOptions>()), kin_(std::make_unique<mb::Kinematics>())
{
  const std::string prefix = where() + ": ";
  mb::SessionOptions &o = *options_;
  std::string path, host = "127.0.0.1";
  long long port = -1;
  bool substeps_given = false;
  for (int i = 3; i < narg; ++i) {
    const std::string kw = arg[i];
    auto value = [&](const char *expected) -> std::string {
      if (i + 1 >= narg)
        error->all(FLERR, prefix + "keyword '" + kw + "' expects " + expected + ", but the command ends there");
      return arg[++i];
    };
    if (kw == "path") {
      path = value("a socket file name");
    } else if (kw == "file") {
      file_ = std::make_unique<mb::FileOptions>();
      file_->in_path = value("MBDyn's input file IN (the loads) and output file OUT (the kinematics)");
      file_->out_path = value("MBDyn's output file OUT (the kinematics) after IN");
    } else if (kw == "sleep") {
      file_sleep_ = parse_double(lmp, kw, value("seconds"), prefix, "seconds (> 0)");
      if (file_sleep_ <= 0) error->all(FLERR, prefix + "keyword 'sleep' expects seconds (> 0), got " + arg[i]);
    } else if (kw == "precision") {
      file_precision_ = static_cast<int>(parse_int(lmp, kw, value("digits"), prefix, "digits (1 to 17)", 1));
      if (file_precision_ > 17) error->all(FLERR, prefix + "keyword 'precision' expects digits (1 to 17), got " + arg[i]);
    } else if (kw == "port") {
      port = parse_int(lmp, kw, value("a TCP port number"), prefix, "a TCP port number (1-65535)", 1);
      if (port > 65535) error->all(FLERR, prefix + "keyword 'port' expects a TCP port number (1-65535), got " + std::to_string(port));
    } else if (kw == "host") {
      host = value("a host name or address");
    } else if (kw == "create") {
      o.role = parse_yes_no(kw, value("yes or no"), prefix, error) ? mb::SocketRole::MbdynCreates
                                                                  : mb::SocketRole::PeerCreates;
    } else if (kw == "coupling") {
      const std::string v = value("loose or tight");
      if (v == "loose") o.coupling = mb::Coupling::Loose;
      else if (v == "tight") o.coupling = mb::Coupling::Tight;
      else error->all(FLERR, prefix + "keyword 'coupling' expects loose or tight, got '" + v + "'");
    } else if (kw == "orientation") {
      const std::string v = value("none, vector, matrix or euler123");
      if (v == "none") o.nodal.rotation = mb::Rotation::None;
      else if (v == "vector") o.nodal.rotation = mb::Rotation::OrientationVector;
      else if (v == "matrix") o.nodal.rotation = mb::Rotation::OrientationMatrix;
      else if (v == "euler123") o.nodal.rotation = mb::Rotation::Euler123;
      else error->all(FLERR, prefix + "keyword 'orientation' expects none, vector, matrix or euler123, got '" + v + "'");
    } else if (kw == "labels") {
      o.nodal.labels = parse_yes_no(kw, value("yes or no"), prefix, error);
    } else if (kw == "accelerations") {
      o.nodal.accelerations = parse_yes_no(kw, value("yes or no"), prefix, error);
    } else if (kw == "reference_node") {
      o.nodal.reference_node = parse_yes_no(kw, value("yes or no"), prefix, error);
    } else if (kw == "reference_forces") {
      use_reference_forces_ = parse_yes_no(kw, value("yes or no"), prefix, error);
      reference_forces_given_ = true;
    } else if (kw == "rotate_reference_forces") {
      rotate_reference_forces_ = parse_yes_no(kw, value("yes or no"), prefix, error);
      reference_forces_given_ = true;
    } else if (kw == "sorted") {
      sorted_ = parse_yes_no(kw, value("yes or no"), prefix, error);
    } else if (kw == "node" || kw == "reference") {
      // `reference atom|group`: the atoms that follow MBDyn's reference node itself; their loads
      // enter the reference record only (MBDyn applies the remainder to the reference node)
      const bool ref = kw == "reference";
      const std::string label = ref ? std::string("reference") : "node " + std::to_string(nodes_.size() + 1);
      const std::string what = value(ref ? "'atom ATOM-ID' or 'group GROUP-ID'"
                                         : "'atom ATOM-ID', 'group GROUP-ID' or 'mesh MESH-ID'");
      NodeSpec n;
      n.is_reference = ref;
      if (ref && reference_body_)
        error->all(FLERR, prefix + "keyword 'reference' given twice: one body follows the reference node");
      if (what == "atom") {
        const std::string v = value("an atom ID");
        n.is_atom = true;
        n.tag = static_cast<tagint>(parse_int(lmp, kw + " atom", v, prefix, "a positive atom ID", 1));
        n.text = "atom " + v;
      } else if (what == "group") {
        n.is_atom = false;
        n.group = value("a group ID");
        const int g = group->find(n.group);
        if (g < 0)
          error->all(FLERR, prefix + label + ": group '" + n.group +
                                "' does not exist (define it with the group command before fix mbdyn)");
        n.groupbit = group->bitmask[g];
        n.text = "group " + n.group;
      } else if (what == "mesh" && !ref) {
        n.is_atom = false;
        n.is_mesh = true;
        n.group = value("the ID of a fix mesh/surface/stress");
        n.mesh = static_cast<int>(meshes_.size());
        meshes_.emplace_back();
        n.text = "mesh " + n.group;
      } else if (ref) {
        error->all(FLERR, prefix + "keyword 'reference' expects 'atom ATOM-ID' or 'group GROUP-ID', got '" + what + "'");
      } else {
        error->all(FLERR, prefix + "keyword 'node' expects 'atom ATOM-ID', 'group GROUP-ID' or 'mesh MESH-ID', got '" + what + "'");
      }
      if (ref) {
        reference_body_ = std::make_unique<NodeSpec>(n);
        continue;
      }
      nodes_.push_back(n);
    } else if (kw == "mapping") {
      // mapping MESH-ID points M: MBDyn's M mapped points, each driving the mesh vertices at its t0 position
      if (deform_) error->all(FLERR, prefix + "keyword 'mapping' given twice: one mesh follows the mapped points");
      deform_mesh_ = value("the ID of a fix mesh/surface/stress");
      const std::string pk = value("'points M'");
      if (pk != "points")
        error->all(FLERR, prefix + "keyword 'mapping' expects 'mapping MESH-ID points M', got '" + pk + "' after the mesh ID");
      const long long m = parse_int(lmp, "mapping points", value("the number of mapped points"), prefix,
                                    "the number of MBDyn's mapped points (>= 3)", 3);
      deform_ = std::make_unique<MbdynDeformDriver>();
      for (long long j = 0; j < m; ++j) {
        NodeSpec n;
        n.is_atom = false;
        n.is_mesh = n.is_vertex = true;
        n.group = deform_mesh_;
        n.text = "mapped point " + std::to_string(j + 1) + " of mesh " + deform_mesh_;
        nodes_.push_back(n);
      }
    } else if (kw == "match_tolerance") {
      match_tolerance_ = parse_double(lmp, kw, value("a distance"), prefix, "a distance (> 0)");
      if (!(match_tolerance_ > 0))
        error->all(FLERR, prefix + "keyword 'match_tolerance' expects a distance (> 0), got " + arg[i]);
      match_tolerance_given_ = true;
    } else if (kw == "substeps") {
      substeps_ = static_cast<int>(parse_int(lmp, kw, value("a positive integer"), prefix, "a positive integer", 1));
      substeps_given = true;
    } else if (kw == "mbdyn_dt") {
      mbdyn_dt_ = parse_double(lmp, kw, value("MBDyn's time step"), prefix, "MBDyn's time step (> 0)");
      if (mbdyn_dt_ <= 0) error->all(FLERR, prefix + "keyword 'mbdyn_dt' expects MBDyn's time step (> 0), got " + arg[i]);
    } else if (kw == "loads") {
      const std::string v = value("average or extrapolate");
      if (v == "average") extrapolate_ = false;
      else if (v == "extrapolate") extrapolate_ = true;
      else error->all(FLERR, prefix + "keyword 'loads' expects average or extrapolate, got '" + v + "'");
    } else if (kw == "predictor") {
      const std::string v = value("mbdyn or correct");
      if (v == "mbdyn") correct_predictor_ = false;
      else if (v == "correct") correct_predictor_ = true;
      else error->all(FLERR, prefix + "keyword 'predictor' expects mbdyn or correct, got '" + v + "'");
    } else if (kw == "resume") {
      resume_ = parse_yes_no(kw, value("yes or no"), prefix, error);
    } else if (kw == "startup_exchange") {
      startup_exchange_ = parse_yes_no(kw, value("yes or no"), prefix, error);
    } else if (kw == "gravity") {
      include_gravity_ = parse_yes_no(kw, value("yes or no"), prefix, error);
    } else if (kw == "connect_timeout") {
      o.connect_timeout_s = parse_double(lmp, kw, value("seconds"), prefix, "seconds (< 0: wait forever)");
    } else if (kw == "io_timeout") {
      o.io_timeout_s = parse_double(lmp, kw, value("seconds"), prefix, "seconds (< 0: wait forever)");
    } else if (kw == "tolerance") {
      tolerance_ = parse_double(lmp, kw, value("a tolerance"), prefix, "a tolerance >= 0");
      if (tolerance_ < 0) error->all(FLERR, prefix + "keyword 'tolerance' expects a tolerance >= 0, got " + arg[i]);
    } else if (kw == "max_iterations") {
      max_iterations_ = static_cast<int>(parse_int(lmp, kw, value("a positive integer"), prefix, "a positive integer", 1));
    } else if (kw == "profile") {
      if (parse_yes_no(kw, value("yes or no"), prefix, error)) profile_.enable();
    } else {
      error->all(FLERR, prefix + "unknown keyword '" + kw + "'; expected one of " + kKeywords);
    }
  }
  if (path.empty() + (port < 0) + !file_ != 2)
    error->all(FLERR, prefix + "give exactly one communicator: 'path FILE' (MBDyn `path`), 'port N [host H]' (MBDyn "
                               "`port`) or 'file IN OUT' (MBDyn's file communicator)");
  if (!file_ && (file_sleep_ > 0 || file_precision_ > 0))
    error->all(FLERR, prefix + "'sleep' and 'precision' are for the file communicator ('file IN OUT')");
  if (deform_) {
    for (const NodeSpec &n : nodes_)
      if (!n.is_vertex)
        error->all(FLERR, prefix + "'mapping' and 'node " + n.text + "' together: with MBDyn's external structural "
                                   "mapping the mapped points are all the points (give either 'mapping' or 'node' entries)");
    if (reference_body_)
      error->all(FLERR, prefix + "'mapping' takes no 'reference atom|group' (the reference node's loads are the "
                                 "total on the mapped points)");
    if (o.nodal.reference_node) {
      // MBDyn's `orientation` then selects the reference node's rotation; the points have none
      if (!o.nodal.has_rotation())
        error->all(FLERR, prefix + "'mapping' with 'reference_node yes' needs the reference node's 'orientation' "
                                   "(matrix, vector or euler123, as MBDyn's element), not none");
      o.nodal.mapping_reference = true;
      o.nodal.reference_rotation = o.nodal.rotation;
      o.nodal.rotation = mb::Rotation::None;
    } else if (o.nodal.has_rotation()) {
      error->all(FLERR, prefix + "'mapping' needs 'orientation none': MBDyn's mapped points carry no orientation "
                                 "(with 'reference_node yes', 'orientation' is the reference node's)");
    }
    if (o.nodal.labels)
      error->all(FLERR, prefix + "'mapping' with 'labels yes' is not supported: MBDyn 1.7.3's external structural "
                                 "mapping fails on its first load message whatever the peer sends (use labels no)");
    if (o.nodal.accelerations)
      error->all(FLERR, prefix + "'mapping' with 'accelerations yes' is not supported: MBDyn 1.7.3 refuses it with "
                                 "static nodes and crashes while parsing it with dynamic ones (use accelerations no)");
  } else if (match_tolerance_given_) {
    error->all(FLERR, prefix + "'match_tolerance' is for 'mapping MESH-ID points M'");
  }
  if (nodes_.empty())
    error->all(FLERR, prefix + "no MBDyn point given: add one 'node atom ID' or 'node group GROUP-ID' per point of the "
                               "external structural element, in the element's order");
  if (substeps_given && mbdyn_dt_ > 0)
    error->all(FLERR, prefix + "give either 'substeps' or 'mbdyn_dt', not both");
  o.nodal.num_points = static_cast<std::uint32_t>(nodes_.size());
  num_points_ = nodes_.size();
  if (reference_body_) nodes_.push_back(*reference_body_);  // the last slot: poses and loads like a point's
  for (std::size_t a = 0; a < nodes_.size(); ++a)
    for (std::size_t b = a + 1; b < nodes_.size(); ++b)
      if (!nodes_[a].is_vertex && nodes_[a].is_atom == nodes_[b].is_atom && nodes_[a].is_mesh == nodes_[b].is_mesh &&
          (nodes_[a].is_atom ? nodes_[a].tag == nodes_[b].tag : nodes_[a].group == nodes_[b].group))
        error->all(FLERR, prefix + slot_name(a) + " and " + slot_name(b) + " are both '" + nodes_[a].text +
                              "': an atom or a mesh can follow only one MBDyn point");
  if (!sorted_ && !o.nodal.labels)
    error->all(FLERR, prefix + "'sorted no' needs 'labels yes' (MBDyn matches loads by label only with labels)");
  if (!o.nodal.reference_node && (reference_forces_given_ || reference_body_))
    error->all(FLERR, prefix + std::string(reference_body_ ? "'reference' needs" : "'reference_forces' and 'rotate_reference_forces' need") +
                          " 'reference_node yes' (MBDyn's `reference node`)");
  if (reference_body_ && !use_reference_forces_)
    error->all(FLERR, prefix + "'reference' needs 'reference_forces yes': with MBDyn's `use reference node forces, no` "
                               "nothing the reference body feels would reach MBDyn");
  o.endpoint = path.empty() ? mb::Endpoint::tcp(host, static_cast<std::uint16_t>(port)) : mb::Endpoint::unix_path(path);
  tight_ = o.coupling == mb::Coupling::Tight;
  if (file_) {
    if (tight_) error->all(FLERR, prefix + "'file IN OUT' supports coupling loose only");
    if (correct_predictor_)
      error->all(FLERR, prefix + "'predictor correct' needs a socket: over 'file IN OUT' MBDyn sends converged states, "
                                 "not predictions");
    if (o.nodal.reference_node) error->all(FLERR, prefix + "'file IN OUT' does not support 'reference_node yes'");
    if (file_->in_path == file_->out_path)
      error->all(FLERR, prefix + "'file IN OUT': IN and OUT are the same file '" + file_->in_path + "'");
    if (file_sleep_ > 0) file_->sleep_s = file_sleep_;
    if (file_precision_ > 0) file_->precision = file_precision_;
    file_->timeout_s = o.io_timeout_s;
    file_->nodal = o.nodal;
  }
  if (!startup_exchange_ && !tight_)
    error->all(FLERR, prefix + "'startup_exchange no' is for coupling tight (in loose MBDyn always exchanges at t0)");
  bcast_.resize(5 * sizeof(long long) + o.nodal.kinematics_payload_bytes());

  const int n = static_cast<int>(nodes_.size());
  poseA_.resize(n);
  poseB_.resize(n);
  cur_.resize(n);
  fsum_.assign(6 * n, 0.0);
  sent_.assign(6 * n, 0.0);

  restart_global = 1;
  vector_flag = 1;
  size_vector = 4 + 3 * static_cast<int>(meshes_.size());
  extvector = 0;
  array_flag = 1;
  size_array_rows = n;
  size_array_cols = 6;
  extarray = 0;
  global_freq = 1;

  // `create, no`: listen now, so MBDyn (which retries its connect for 60 s) can be started
  // any time after this command (spec §1).
  if (o.role == mb::SocketRole::PeerCreates) {
    std::string err;
    if (comm->me == 0) {
      try {
        listener_ = std::make_unique<mb::SocketListener>(o.endpoint);
      } catch (const std::exception &e) {
        err = e.what();
      }
    }
    int len = static_cast<int>(err.size());
    MPI_Bcast(&len, 1, MPI_INT, 0, world);
    if (len) {
      err.resize(len);
      MPI_Bcast(&err[0], len, MPI_CHAR, 0, world);
      error->all(FLERR, prefix + "cannot listen on " + o.endpoint.describe() + " (create no): " + err);
    }
  }
}

FixMBDyn::~FixMBDyn()
{
  // Leave MBDyn in a clean state (spec P13): if it already ended, read its 5; otherwise ask it
  // to stop at the end of its step (5 instead of loads) and wait for its final 5. Bounded by
  // io_timeout; after an error only the session's own abort (send 5) happens.
  if (comm->me == 0 && session_ && !failed_ && !ended_ && !session_->finished()) {
    try {
      const bool answered = substep_ == 0 && !t0_answer_pending_ && !first_is_step1_;
      bool done = false;
      if (answered) done = !session_->receive().is_kinematics();
      if (!done) {
        session_->request_stop();
        session_->receive();
      }
    } catch (const std::exception &) {
    }
  }
  session_.reset();
  listener_.reset();
}

namespace {
// LAMMPS takes the source file as a std::string: built once, not per call (FLERR allocated one per atom and step).
const std::string &here()
{
  static const std::string file = __FILE__;
  return file;
}
}  // namespace

namespace {
// Ends a profiled phase on every way out of a fix call (returns and errors alike).
struct PhaseEnd {
  ExchangeProfile &profile;
  ExchangeProfile::Phase phase;
  ~PhaseEnd() { profile.lap(phase); }
};
}  // namespace

std::string FixMBDyn::where() const { return std::string("Fix mbdyn (id ") + id + ")"; }

int FixMBDyn::setmask()
{
  return PRE_EXCHANGE | POST_INTEGRATE | POST_FORCE | END_OF_STEP;
}

void FixMBDyn::fail_all(const std::string &why)
{
  failed_ = true;
  if (comm->me == 0 && session_) session_->abort();  // MBDyn must not wait for us (spec P4)
  std::fflush(nullptr);                             // dumps and logs written so far are kept
  error->all(FLERR, where() + ": " + why);
}

void FixMBDyn::init()
{
  const std::string prefix = where() + ": ";
  if (mbdyn_dt_ > 0) {
    const double n = mbdyn_dt_ / update->dt;
    const long long ni = std::llround(n);
    if (ni < 1 || std::fabs(n - static_cast<double>(ni)) > 1e-6 * n)
      error->all(FLERR, prefix + "mbdyn_dt " + num(mbdyn_dt_) + " must be an integer multiple of the LAMMPS "
                 "timestep " + num(update->dt) + " (one MBDyn step = N LAMMPS steps)");
    if (bound_ && !restored_ && ni != substeps_)  // after read_restart: check_restored_config says it
      error->all(FLERR, prefix + "the LAMMPS timestep changed during the coupling: " + std::to_string(ni) +
                            " substeps instead of " + std::to_string(substeps_));
    substeps_ = static_cast<int>(ni);
  }
  check_restored_config();
  if (!atom->tag_enable) error->all(FLERR, prefix + "requires atom IDs");
  if (update->integrate_style && std::strncmp(update->integrate_style, "respa", 5) == 0)
    error->all(FLERR, prefix + "does not support run_style respa (it reads the loads in post_force); use run_style verlet");
  check_atoms();
  for (const NodeSpec &n : nodes_)
    if (n.is_mesh && !n.is_vertex) meshes_[n.mesh].attach(lmp, n.group, prefix + "node " + n.text);
  if (deform_) deform_->attach(lmp, deform_mesh_, prefix);

  // How many coupled atoms another fix acts on.
  auto coupled_in = [&](Fix *f) {
    bigint mine = 0, all = 0;
    for (int a = 0; a < atom->nlocal; ++a) {
      if (!(atom->mask[a] & f->groupbit)) continue;
      for (const NodeSpec &n : nodes_)
        if (n.is_atom ? atom->tag[a] == n.tag : (atom->mask[a] & n.groupbit) != 0) {
          ++mine;
          break;
        }
    }
    MPI_Allreduce(&mine, &all, 1, MPI_LMP_BIGINT, MPI_SUM, world);
    return all;
  };
  const int me = modify->find_fix(id);
  // end_of_step puts the coupled atoms' velocities back only if another fix can change them
  // (integrators, and fixes that act at integration or end-of-step time, e.g. temp/rescale).
  constexpr int moves_v = INITIAL_INTEGRATE | POST_INTEGRATE | FINAL_INTEGRATE | END_OF_STEP;
  others_move_coupled_ = false;
  for (int i = 0; i < modify->nfix; ++i) {
    Fix *f = modify->fix[i];
    if (f == this || !(f->time_integrate || (modify->fmask[i] & moves_v))) continue;
    const bigint n = coupled_in(f);
    if (n > 0) others_move_coupled_ = true;
    if (!f->time_integrate) continue;
    if (n > 0 && comm->me == 0)
      error->warning(FLERR, prefix + "fix " + std::string(f->id) + " (style " + f->style + ") integrates " +
                                std::to_string(n) + " coupled atoms; fix mbdyn overrides their motion, so leave "
                                "them out of its group");
  }
  // Gravity is included in the loads only if fix gravity's post_force runs before ours.
  for (int i = 0; i < modify->nfix; ++i) {
    Fix *f = modify->fix[i];
    if (std::strncmp(f->style, "gravity", 7) != 0) continue;
    // only a gravity fix acting on coupled atoms matters
    const bigint touched = coupled_in(f);
    if (touched == 0) continue;
    if (!include_gravity_ && i < me)
      error->all(FLERR, prefix + "gravity no (the default) needs fix " + f->id + " (style " + f->style +
                            ") to be defined after fix mbdyn (it acts on " + std::to_string(touched) +
                            " coupled atoms), so the loads are read before gravity is added; "
                            "move it, or use 'gravity yes' to send the coupled atoms' weight to MBDyn");
    if (include_gravity_ && i > me)
      error->all(FLERR, prefix + "gravity yes needs fix " + std::string(f->id) + " (style " + f->style +
                            ") to be defined before fix mbdyn, so the loads are read after gravity is added");
  }
}

void FixMBDyn::check_atoms()
{
  const std::string prefix = where() + ": ";
  const int nlocal = atom->nlocal;
  for (std::size_t k = 0; k < nodes_.size(); ++k) {
    const NodeSpec &n = nodes_[k];
    bigint count = 0;
    if (n.is_atom) {
      bigint mine = 0;
      for (int i = 0; i < nlocal; ++i)
        if (atom->tag[i] == n.tag) ++mine;
      MPI_Allreduce(&mine, &count, 1, MPI_LMP_BIGINT, MPI_SUM, world);
      if (count == 0)
        error->all(FLERR, prefix + slot_name(k) + " (" + n.text + "): no atom with ID " +
                              std::to_string(n.tag) + " exists");
    } else if (!n.is_mesh) {
      const int g = group->find(n.group);
      if (g < 0)
        error->all(FLERR, prefix + slot_name(k) + " (" + n.text + "): the group was deleted");
      if (group->count(g) == 0)
        error->all(FLERR, prefix + slot_name(k) + " (" + n.text + "): the group has no atoms");
    }
  }
}

void FixMBDyn::open_session()
{
  std::string err;
  if (comm->me == 0) {
    try {
      if (file_)
        file_session_ = std::make_unique<mb::FileSession>(*file_);
      else if (listener_)
        session_ = std::make_unique<mb::PeerSession>(mb::PeerSession::accept(*listener_, *options_));
      else
        session_ = std::make_unique<mb::PeerSession>(mb::PeerSession::open(*options_));
    } catch (const std::exception &e) {
      err = e.what();
      if (err.empty()) err = "unknown error";
    }
  }
  int len = static_cast<int>(err.size());
  MPI_Bcast(&len, 1, MPI_INT, 0, world);
  if (len) {
    err.resize(len);
    MPI_Bcast(&err[0], len, MPI_CHAR, 0, world);
    if (file_) fail_all("cannot couple to MBDyn over the files " + file_->in_path + " and " + file_->out_path + ": " + err);
    fail_all("cannot couple to MBDyn over " + options_->endpoint.describe() + " (" +
             (listener_ ? "create no: waiting for MBDyn to connect" : "create yes: connecting to MBDyn") +
             ", connect_timeout " + num(options_->connect_timeout_s) + " s, " +
             options_->nodal.describe() + ", " + mb::coupling_name(options_->coupling) + " coupling): " + err);
  }
}

FixMBDyn::Message FixMBDyn::receive_broadcast(const char *expecting)
{
  // One broadcast per message: a header (status, command, step, iteration, error length) and the
  // raw payload in the same buffer; none on 1 rank.
  constexpr std::size_t head_bytes = 5 * sizeof(long long);
  const bool parallel = comm->nprocs > 1;
  Message m;
  std::string err;
  if (comm->me == 0) {
    try {
      const mb::Received r = file_session_ ? file_session_->receive() : session_->receive();
      if (!r.is_kinematics()) {
        m.status = 1;
      } else {
        m.command = static_cast<int>(kinematics().command);
        m.step = static_cast<long long>(r.step);
        m.iteration = static_cast<int>(r.iteration);
        if (parallel) {  // the other ranks decode these bytes
          const auto &raw = file_session_ ? file_session_->raw_payload() : session_->raw_payload();
          std::memcpy(bcast_.data() + head_bytes, raw.data(), raw.size());
        }
      }
    } catch (const std::exception &e) {
      m.status = 2;
      err = e.what();
    }
  }
  if (parallel) {
    long long head[5] = {m.status, m.command, m.step, m.iteration, static_cast<long long>(err.size())};
    std::memcpy(bcast_.data(), head, head_bytes);
    MPI_Bcast(bcast_.data(), static_cast<int>(bcast_.size()), MPI_BYTE, 0, world);
    std::memcpy(head, bcast_.data(), head_bytes);
    m.status = static_cast<int>(head[0]);
    m.command = static_cast<int>(head[1]);
    m.step = head[2];
    m.iteration = static_cast<int>(head[3]);
    if (m.status == 2) {
      err.resize(static_cast<std::size_t>(head[4]));
      if (head[4]) MPI_Bcast(&err[0], static_cast<int>(head[4]), MPI_CHAR, 0, world);
    }
  }
  if (m.status == 2)
    fail_all(std::string("while waiting for ") + expecting + " at LAMMPS step " + std::to_string(update->ntimestep) +
             " (MBDyn step " + std::to_string(mbdyn_step_) + "): " + err);
  if (m.status == 0) {
    // Every rank decodes the same bytes (spec P5); rank 0 already did (and validated them) in receive().
    if (comm->me != 0)
      mb::decode_kinematics_into(options_->nodal, static_cast<mb::Command>(m.command), bcast_.data() + head_bytes,
                                 bcast_.size() - head_bytes, *kin_);
    ++messages_;
  }
  return m;
}

std::string FixMBDyn::slot_name(std::size_t k) const
{
  return k == num_points_ ? std::string("reference") : "node " + std::to_string(k + 1);
}

const mb::Kinematics &FixMBDyn::kinematics() const
{
  if (comm->me != 0) return *kin_;
  return file_session_ ? file_session_->kinematics() : session_->kinematics();
}

void FixMBDyn::decode_to_global(std::vector<Pose> &out)
{
  decode_poses(out);
  check_poses(out);
}

void FixMBDyn::decode_poses(std::vector<Pose> &out)
{
  const mb::Kinematics &k = kinematics();
  const bool rot = options_->nodal.has_rotation();
  if (k.has_reference) {
    ref_R_ = k.reference_rotation != mb::Rotation::None ? k.reference_rotation_matrix() : M9{1, 0, 0, 0, 1, 0, 0, 0, 1};
    ref_x_ = k.reference.x;
  } else if (k.rotation == mb::Rotation::OrientationMatrix || !rot) {
    // MBDyn's default layout (global points, the matrix column-major on the wire) or no rotation:
    // straight from the message's arrays, the values as the general loop below gives them.
    const double *x = k.x.data(), *v = k.v.data(), *w = rot ? k.omega.data() : nullptr;
    const double *o = rot ? k.orientation.data() : nullptr;
    for (std::size_t i = 0; i < out.size(); ++i, x += 3, v += 3) {
      Pose &p = out[i];
      p.x = {x[0], x[1], x[2]};
      p.v = {v[0], v[1], v[2]};
      if (rot) {
        p.w = {w[3 * i], w[3 * i + 1], w[3 * i + 2]};
        p.R = mb::matrix_from_wire_column_major(o + 9 * i);
      } else {
        p.w = {0, 0, 0};
        p.R = {1, 0, 0, 0, 1, 0, 0, 0, 1};
      }
    }
    return;
  }
  for (std::size_t i = 0; i < num_points_; ++i) {
    Pose &p = out[i];  // every field is written below
    const V3 x = k.position(i), v = k.velocity(i);
    V3 w{0, 0, 0};
    if (rot) w = {k.omega[3 * i], k.omega[3 * i + 1], k.omega[3 * i + 2]};
    M9 R{1, 0, 0, 0, 1, 0, 0, 0, 1};
    if (k.rotation == mb::Rotation::OrientationMatrix)  // MBDyn's default: no format dispatch, no bounds check
      R = mb::matrix_from_wire_column_major(&k.orientation[9 * i]);
    else if (rot) {
      R = k.rotation_matrix(i);
    }
    if (!k.has_reference) {
      p.x = x;
      p.v = v;
      p.w = w;
      p.R = R;
    } else {
      // Points arrive relative to the reference node, in its frame (spec §4.3).
      const V3 &xr = k.reference.x, &vr = k.reference.v;
      const V3 wr = options_->nodal.record_has_omega() ? k.reference.omega : V3{0, 0, 0};
      const V3 d = mat_vec(ref_R_, x.data());
      const V3 wxd = cross(wr.data(), d.data());
      const V3 vv = mat_vec(ref_R_, v.data());
      const V3 ww = mat_vec(ref_R_, w.data());
      for (int c = 0; c < 3; ++c) {
        p.x[c] = xr[c] + d[c];
        p.v[c] = vr[c] + wxd[c] + vv[c];
        p.w[c] = wr[c] + ww[c];
      }
      p.R = mat_mul(ref_R_, R);
    }
  }
  if (reference_body_) {  // the reference body's slot: the reference node's own absolute pose
    Pose &p = out[num_points_];
    p.x = k.reference.x;
    p.v = k.reference.v;
    p.w = rot ? k.reference.omega : V3{0, 0, 0};
    p.R = ref_R_;
  }
}

void FixMBDyn::bind_atoms()
{
  // Each coupled atom gets its body coordinates r relative to its point, in the point's frame,
  // from the atom positions at the t0 message: x_atom = x_point + R r from then on. A single
  // atom (node atom ID) sits on the point (r = 0).
  std::unordered_map<tagint, int> atom_node;
  for (std::size_t k = 0; k < nodes_.size(); ++k)
    if (nodes_[k].is_atom) atom_node[nodes_[k].tag] = static_cast<int>(k);
  std::vector<double> mine;
  double **x = atom->x;
  for (int i = 0; i < atom->nlocal; ++i) {
    std::vector<int> hits;
    auto it = atom_node.find(atom->tag[i]);
    if (it != atom_node.end()) hits.push_back(it->second);
    for (std::size_t k = 0; k < nodes_.size(); ++k)
      if (!nodes_[k].is_atom && (atom->mask[i] & nodes_[k].groupbit)) hits.push_back(static_cast<int>(k));
    for (int k : hits) {
      double r[3] = {0, 0, 0};
      if (!nodes_[k].is_atom) {
        double d[3] = {x[i][0] - poseA_[k].x[0], x[i][1] - poseA_[k].x[1], x[i][2] - poseA_[k].x[2]};
        dembridge::minimum_image(domain, here(), __LINE__, d);
        const V3 rl = mat_t_vec(poseA_[k].R, d);
        r[0] = rl[0];
        r[1] = rl[1];
        r[2] = rl[2];
      }
      mine.insert(mine.end(), {static_cast<double>(atom->tag[i]), static_cast<double>(k), r[0], r[1], r[2]});
    }
  }
  int nme = static_cast<int>(mine.size()), nprocs = comm->nprocs;
  std::vector<int> counts(nprocs), displs(nprocs, 0);
  MPI_Allgather(&nme, 1, MPI_INT, counts.data(), 1, MPI_INT, world);
  int total = 0;
  for (int p = 0; p < nprocs; ++p) {
    displs[p] = total;
    total += counts[p];
  }
  std::vector<double> all(total);
  MPI_Allgatherv(mine.data(), nme, MPI_DOUBLE, all.data(), counts.data(), displs.data(), MPI_DOUBLE, world);
  members_.clear();
  std::vector<long long> per_node(nodes_.size(), 0);
  for (int j = 0; j + 4 < total; j += 5) {
    const tagint tag = static_cast<tagint>(all[j]);
    Member m;
    m.node = static_cast<int>(all[j + 1]);
    m.r[0] = all[j + 2];
    m.r[1] = all[j + 3];
    m.r[2] = all[j + 4];
    auto ins = members_.emplace(tag, m);
    if (!ins.second)
      fail_all("atom " + std::to_string(tag) + " belongs to " + slot_name(ins.first->second.node) + " (" +
               nodes_[ins.first->second.node].text + ") and to " + slot_name(m.node) + " (" +
               nodes_[m.node].text + "): an atom can follow only one MBDyn point");
    ++per_node[m.node];
  }
  for (std::size_t k = 0; k < nodes_.size(); ++k)
    if (nodes_[k].is_mesh && !nodes_[k].is_vertex) meshes_[nodes_[k].mesh].bind(poseA_[k].x, poseA_[k].R);
  if (deform_) {
    vertex_x_.resize(num_points_);
    for (std::size_t k = 0; k < num_points_; ++k) vertex_x_[k] = poseA_[k].x;
    const std::string why = deform_->bind(vertex_x_, match_tolerance_);
    if (!why.empty())
      fail_all("mapping " + deform_mesh_ + " points " + std::to_string(num_points_) + ": " + why + " (match_tolerance " +
               num(match_tolerance_) + "; each vertex of the mesh as placed must be at one mapped point of MBDyn's t0 message)");
  }
  for (std::size_t k = 0; k < nodes_.size(); ++k)
    if (per_node[k] == 0 && !nodes_[k].is_mesh)
      fail_all(slot_name(k) + " (" + nodes_[k].text + "): no atom to couple");
  index_members();
  bound_ = true;
}

void FixMBDyn::index_members()
{
  node_radius_.assign(nodes_.size(), 0.0);
  for (const auto &tm : members_) {
    const Member &m = tm.second;
    node_radius_[m.node] = std::max(node_radius_[m.node], std::sqrt(m.r[0] * m.r[0] + m.r[1] * m.r[1] + m.r[2] * m.r[2]));
  }
  allbits_ = 0;
  bool any_atom = false;
  for (const NodeSpec &n : nodes_) {
    if (n.is_atom) any_atom = true;
    else if (!n.is_mesh) allbits_ |= n.groupbit;
  }
  if (any_atom) allbits_ = 0;  // no cheap mask filter then
  // The coupled atoms by tag, for the per-step loops: a few map lookups instead of a hash lookup per
  // local atom (10^4 atoms, 100 nodes: ~1e4 lookups a step otherwise).
  member_list_.assign(members_.begin(), members_.end());
  std::sort(member_list_.begin(), member_list_.end(),
            [](const std::pair<tagint, Member> &a, const std::pair<tagint, Member> &b) { return a.first < b.first; });
  one_atom_per_node_ = true;
  for (const NodeSpec &n : nodes_)
    if (!n.is_atom) one_atom_per_node_ = false;
  node_tags_.clear();
  node_index_.clear();
  ++tags_version_;  // the node atoms' local indices must be looked up again
  for (const auto &tm : member_list_) {
    node_tags_.push_back(tm.first);
    node_index_.push_back(tm.second.node);
  }
}

void FixMBDyn::interpolate(double s, std::vector<Pose> &out) const
{
  // Cubic Hermite on positions (C1 with the velocities MBDyn sent), its derivative for the
  // velocities, slerp for the orientation, linear angular velocity. s = j / N in (0, 1].
  const double T = substeps_ * update->dt;
  const double s2 = s * s, s3 = s2 * s;
  const double h00 = 2 * s3 - 3 * s2 + 1, h10 = s3 - 2 * s2 + s, h01 = -2 * s3 + 3 * s2, h11 = s3 - s2;
  const double d00 = 6 * s2 - 6 * s, d10 = 3 * s2 - 4 * s + 1, d01 = -6 * s2 + 6 * s, d11 = 3 * s2 - 2 * s;
  if (s >= 1.0) {  // the end of the MBDyn step (every step with 1 sub-step): pose B itself
    for (std::size_t k = 0; k < out.size(); ++k) out[k] = poseB_[k];
    return;
  }
  for (std::size_t k = 0; k < out.size(); ++k) {
    const Pose &A = poseA_[k], &B = poseB_[k];
    Pose &P = out[k];
    for (int c = 0; c < 3; ++c) {
      P.x[c] = h00 * A.x[c] + h10 * T * A.v[c] + h01 * B.x[c] + h11 * T * B.v[c];
      P.v[c] = (d00 * A.x[c] + d01 * B.x[c]) / T + d10 * A.v[c] + d11 * B.v[c];
      P.w[c] = (1 - s) * A.w[c] + s * B.w[c];
    }
    P.R = slerp(A.R, B.R, s);
  }
}

// The atom map is current inside a run's steps (not necessarily in setup, before the exchange).
bool FixMBDyn::fast_member_lookup() const
{
  return atom->map_style != Atom::MAP_NONE && !update->setupflag;
}

void FixMBDyn::apply_pose(const std::vector<Pose> &poses, bool set_x)
{
  if (node_atoms_fast_path()) return apply_pose_node_atoms(poses, set_x);  // only node atom entries
  double **x = atom->x, **v = atom->v;
  double **omega = atom->omega_flag ? atom->omega : nullptr;
  const bool rot = options_->nodal.has_rotation();
  const imageint image0 = ((imageint) IMGMAX << IMG2BITS) | ((imageint) IMGMAX << IMGBITS) | IMGMAX;
  if (set_x)
    for (std::size_t k = 0; k < nodes_.size(); ++k)
      if (nodes_[k].is_mesh && !nodes_[k].is_vertex)
        meshes_[nodes_[k].mesh].move_to(poses[k].x, poses[k].R, poses[k].v, poses[k].w);
  if (set_x && deform_) {
    vertex_x_.resize(num_points_);
    vertex_v_.resize(num_points_);
    for (std::size_t k = 0; k < num_points_; ++k) {
      vertex_x_[k] = poses[k].x;
      vertex_v_[k] = poses[k].v;
    }
    deform_->move_to(vertex_x_, vertex_v_);
  }
  // remap only where it can change x: a periodic dimension, or a triclinic box's round trip; an
  // orthogonal box's remap leaves a position inside [lo, hi) as it is, so those skip the call
  const bool remap = domain->xperiodic || domain->yperiodic || domain->zperiodic || domain->triclinic;
  constexpr double inf = std::numeric_limits<double>::infinity();
  const int periodic[3] = {domain->xperiodic, domain->yperiodic, domain->zperiodic};
  double lo[3], hi[3];  // [lo, hi) of the periodic dimensions, everything in the others
  for (int c = 0; c < 3; ++c) {
    lo[c] = periodic[c] ? domain->boxlo[c] : -inf;
    hi[c] = periodic[c] ? domain->boxhi[c] : inf;
  }
  auto inside = [&](const double *xi) {
    return xi[0] >= lo[0] && xi[0] < hi[0] && xi[1] >= lo[1] && xi[1] < hi[1] && xi[2] >= lo[2] && xi[2] < hi[2];
  };
  auto move = [&](int i, const Member &m) {
    const Pose &P = poses[m.node];
    const bool on_point = m.r[0] == 0.0 && m.r[1] == 0.0 && m.r[2] == 0.0;  // node atom: R r = 0
    const V3 Rr = on_point ? V3{0, 0, 0} : mat_vec(P.R, m.r);
    const V3 wxr = on_point ? V3{0, 0, 0} : cross(P.w.data(), Rr.data());
    if (set_x) {
      for (int c = 0; c < 3; ++c) x[i][c] = P.x[c] + Rr[c];
      atom->image[i] = image0;
      if (remap && (domain->triclinic || !inside(x[i]))) domain->remap(x[i], atom->image[i]);
    }
    for (int c = 0; c < 3; ++c) v[i][c] = P.v[c] + wxr[c];
    if (omega && rot)
      for (int c = 0; c < 3; ++c) omega[i][c] = P.w[c];
  };
  // Each atom is moved on its own: visiting the members instead of all local atoms changes nothing.
  if (fast_member_lookup()) {
    for (const auto &tm : member_list_) {
      const int i = atom->map(tm.first);
      if (i >= 0 && i < atom->nlocal && atom->tag[i] == tm.first) move(i, tm.second);
    }
    return;
  }
  for (int i = 0; i < atom->nlocal; ++i) {
    if (allbits_ && !(atom->mask[i] & allbits_)) continue;
    auto it = members_.find(atom->tag[i]);
    if (it != members_.end()) move(i, it->second);
  }
}

void FixMBDyn::accumulate_loads(const std::vector<Pose> &poses, std::vector<double> &out6)
{
  // Force on each point = sum of f of its atoms; moment about the point = sum of (x - x_p) x f
  // plus the atoms' torques (spec §4.3: global frame, moment about the point).
  const int n = static_cast<int>(nodes_.size());
  std::vector<double> &local = local_loads_;
  double **x = atom->x, **f = atom->f;
  double **torque = atom->torque_flag ? atom->torque : nullptr;
  // minimum_image changes nothing without a periodic dimension, nor (orthogonal box) an arm within
  // half the box in every periodic dimension: the common case skips the call
  const bool periodic = domain->xperiodic || domain->yperiodic || domain->zperiodic;
  constexpr double inf = std::numeric_limits<double>::infinity();
  const bool triclinic = domain->triclinic != 0;
  const double half[3] = {domain->xperiodic ? domain->prd_half[0] : inf, domain->yperiodic ? domain->prd_half[1] : inf,
                          domain->zperiodic ? domain->prd_half[2] : inf};
  auto wrap = [&](double *d) {
    if (triclinic || std::fabs(d[0]) > half[0] || std::fabs(d[1]) > half[1] || std::fabs(d[2]) > half[2])
      dembridge::minimum_image(domain, here(), __LINE__, d);
  };
  auto add = [&](int i, int k) {
    double d[3] = {x[i][0] - poses[k].x[0], x[i][1] - poses[k].x[1], x[i][2] - poses[k].x[2]};
    if (periodic) wrap(d);
    const V3 m = cross(d, f[i]);
    for (int c = 0; c < 3; ++c) {
      local[6 * k + c] += f[i][c];
      local[6 * k + 3 + c] += m[c] + (torque ? torque[i][c] : 0.0);
    }
  };
  if (node_atoms_fast_path()) {
    accumulate_loads_node_atoms(poses, local);
  } else {
    local.assign(6 * n, 0.0);
    for (int i = 0; i < atom->nlocal; ++i) {
      if (allbits_ && !(atom->mask[i] & allbits_)) continue;
      auto it = members_.find(atom->tag[i]);
      if (it != members_.end()) add(i, it->second.node);
    }
  }
  if (comm->nprocs > 1) {
    out6.resize(6 * n);
    MPI_Allreduce(local.data(), out6.data(), 6 * n, MPI_DOUBLE, MPI_SUM, world);
  } else {
    out6.swap(local);  // both keep their storage from step to step
  }
  for (int k = 0; k < n; ++k)
    if (nodes_[k].is_mesh && !nodes_[k].is_vertex) meshes_[nodes_[k].mesh].loads(poses[k].x, &out6[6 * k]);
  if (deform_) deform_->loads(out6.data());
}

void FixMBDyn::send_answer(const std::vector<double> &loads6, bool converged, const char *what)
{
  const mb::NodalConfig &c = options_->nodal;
  if (!answer_) answer_ = std::make_unique<mb::Loads>(c);  // made once: every slot is set below
  mb::Loads &l = *answer_;
  V3 F0{0, 0, 0}, M0{0, 0, 0};
  for (std::size_t k = 0; k < nodes_.size(); ++k) {
    const double *F = &loads6[6 * k], *M = &loads6[6 * k + 3];
    if (c.reference_node) {
      // Loads in the reference node's frame (spec §4.3); the reference record carries the total
      // resultant about x_ref (MBDyn's `use reference node forces`): the points' loads and the
      // reference body's, so MBDyn applies to the reference node what its body felt.
      const double dx[3] = {cur_[k].x[0] - ref_x_[0], cur_[k].x[1] - ref_x_[1], cur_[k].x[2] - ref_x_[2]};
      const V3 dxf = cross(dx, F);
      for (int a = 0; a < 3; ++a) {
        F0[a] += F[a];
        M0[a] += M[a] + dxf[a];
      }
      if (k == num_points_) break;  // the reference body: in the record only
      const V3 Fl = mat_t_vec(ref_R_, F), Ml = mat_t_vec(ref_R_, M);
      for (int a = 0; a < 3; ++a) l.force[3 * k + a] = Fl[a];
      if (c.has_rotation())
        for (int a = 0; a < 3; ++a) l.moment[3 * k + a] = Ml[a];
    } else {
      for (int a = 0; a < 3; ++a) l.force[3 * k + a] = F[a];
      if (c.has_rotation())
        for (int a = 0; a < 3; ++a) l.moment[3 * k + a] = M[a];
    }
  }
  if (c.reference_node) {
    // `use reference node forces, no`: MBDyn reads the record and ignores it; zeros say so.
    // `rotate reference node forces, no`: the record in the global frame.
    const V3 zero{0, 0, 0};
    l.reference_force = !use_reference_forces_ ? zero : rotate_reference_forces_ ? mat_t_vec(ref_R_, F0.data()) : F0;
    if (c.record_has_omega())
      l.reference_moment = !use_reference_forces_ ? zero : rotate_reference_forces_ ? mat_t_vec(ref_R_, M0.data()) : M0;
  }
  // compute_array reads the answer itself when it holds all six global components
  if (!answer_is_global6()) sent_ = loads6;
  std::string err;
  if (comm->me == 0) {
    try {
      if (file_session_) file_session_->send_loads(l);
      else session_->send_loads(l, converged);
    } catch (const std::exception &e) {
      err = e.what();
      if (err.empty()) err = "unknown error";
    }
  }
  int len = static_cast<int>(err.size());
  if (comm->nprocs > 1) MPI_Bcast(&len, 1, MPI_INT, 0, world);
  if (len) {
    err.resize(len);
    if (comm->nprocs > 1) MPI_Bcast(&err[0], len, MPI_CHAR, 0, world);
    fail_all(std::string("while sending ") + what + " at LAMMPS step " + std::to_string(update->ntimestep) +
             " (MBDyn step " + std::to_string(mbdyn_step_) + "): " + err);
  }
  ++exchanges_;
}

void FixMBDyn::stop_run_at_end(const Message &)
{
  ended_ = true;
  if (comm->me == 0)
    error->warning(FLERR, where() + ": MBDyn ended the simulation (sent 5) after MBDyn step " +
                              std::to_string(mbdyn_step_) + "; stopping this run at LAMMPS step " +
                              std::to_string(update->ntimestep) + ", the coupled atoms are held still from now on");
  for (Pose &p : cur_) {
    p.v = {0, 0, 0};
    p.w = {0, 0, 0};
  }
  apply_pose(cur_, false);
  timer->force_timeout();
}

double FixMBDyn::pose_change(const std::vector<Pose> &a, const std::vector<Pose> &b) const
{
  double d = 0;
  for (std::size_t k = 0; k < a.size(); ++k) {
    for (int c = 0; c < 3; ++c) d = std::max(d, std::fabs(a[k].x[c] - b[k].x[c]));
    for (int c = 0; c < 9; ++c) d = std::max(d, std::fabs(a[k].R[c] - b[k].R[c]));
  }
  return d;
}


FixMBDyn::PredictorEvidence FixMBDyn::follows_crank_nicolson(const std::vector<Pose> &prev, const std::vector<Pose> &msg,
                                                             double T)
{
  // Crank nicolson's predictions of consecutive steps satisfy, to round-off,
  //   x_p,k - x_p,k-1 = T/2 (3 v_p,k - v_p,k-1)
  // (x_p = x + T v and v_p = v of the converged states, which follow the trapezoidal rule).
  // Measured on the recorded real MBDyn runs: <= 1.3e-13 relative. A multistep predictor misses
  // it by O((T w)^3), e.g. 1e-7 relative for w T = 0.005. A point that does not translate (a
  // hinge) tells nothing either way.
  constexpr double kTolerance = 1e-10, kMoving = 1e-8;
  bool moved = false;
  for (std::size_t k = 0; k < msg.size(); ++k)
    for (int c = 0; c < 3; ++c) {
      const double P = msg[k].x[c], Q = prev[k].x[c], Pv = msg[k].v[c], Qv = prev[k].v[c];
      const double step = T * (3 * std::fabs(Pv) + std::fabs(Qv)), scale = std::fabs(P) + std::fabs(Q) + step;
      if (std::fabs(P - Q - 0.5 * T * (3 * Pv - Qv)) > kTolerance * scale) return PredictorEvidence::Other;
      if (step > kMoving * scale) moved = true;
    }
  return moved ? PredictorEvidence::CrankNicolson : PredictorEvidence::Unknown;
}

void FixMBDyn::correct_prediction(const std::vector<Pose> &msg)
{
  // MBDyn's crank nicolson predictor sends v_p = v_{k-1}, x_p = x_{k-1} + T v_{k-1} (and the
  // orientation advanced by T w_{k-1}): an O(T) error in v and O(T^2) in x that enters the load
  // frozen for the whole step, so loose coupling is first order. The previous message carried
  // v_{k-2}; the converged state of step k-1 is recovered from this one, and the end-of-step pose
  // is extrapolated to second order: v* = 2 v_{k-1} - v_{k-2}, x* = x_{k-1} + T/2 (v_{k-1} + v*)
  // (the trapezoidal rule), the same for w and the orientation. Pose A of the sub-step
  // interpolation becomes the recovered converged state.
  const double T = substeps_ * update->dt;
  // the first step's message (no previous one): corrected only with accelerations, from a_{k-1}
  // alone (MBDyn's first step is a crank nicolson step whatever its method)
  const bool first = prev_msg_.size() != msg.size();
  const bool acc = uses_accelerations() && !msg_acc_.empty() && (first || prev_acc_.size() == msg_acc_.size());
  if (first && !acc) {
    prev_msg_ = msg;
    prev_acc_ = msg_acc_;
    return;
  }
  const PredictorEvidence evidence = first              ? PredictorEvidence::CrankNicolson
                                     : predictor_is_cn_ ? follows_crank_nicolson(prev_msg_, msg, T)
                                                        : PredictorEvidence::Other;
  if (evidence == PredictorEvidence::Unknown && !warned_unverified_ && comm->me == 0) {
    warned_unverified_ = true;
    error->warning(FLERR, where() + ": predictor correct is right only for MBDyn's `method: crank nicolson`, and "
                              "no coupled point translates, so the method cannot be checked from the messages; "
                              "with another method use predictor mbdyn");
  }
  if (predictor_is_cn_ && evidence == PredictorEvidence::Other) {
    // Another integrator (ms, hope, ...): the recovery below would be wrong and make the coupling
    // first order, where MBDyn's own prediction is already good. From here on the atoms take
    // MBDyn's pose as sent, as with predictor mbdyn.
    predictor_is_cn_ = false;
    if (comm->me == 0)
      error->warning(FLERR, where() + ": predictor correct: MBDyn's predictions at MBDyn step " +
                                std::to_string(mbdyn_step_) + " do not follow crank nicolson's predictor (MBDyn's "
                                "`method` is another one, or a point has an offset on a turning node); using "
                                "MBDyn's predicted pose as sent (predictor mbdyn) for the rest of the run");
  }
  if (!predictor_is_cn_) {
    prev_msg_ = msg;
    prev_acc_ = msg_acc_;
    return;
  }
  for (std::size_t k = 0; k < msg.size(); ++k) {
    const Pose &P = msg[k], &Q = first ? msg[k] : prev_msg_[k];
    Pose A = P, B = P;
    V3 back{}, half{};
    // With MBDyn's accelerations (crank nicolson's prediction sends those of the converged step
    // k-1), the end-of-step velocity is the trapezoidal rule with a_k extrapolated linearly from
    // a_{k-1} and a_{k-2}: v* - v_{k-1} = T/2 (3 a_{k-1} - a_{k-2}), one order more than
    // v_{k-1} - v_{k-2} = T/2 (a_{k-1} + a_{k-2}) below. At the first step: v* - v_0 = T a_0.
    const double *a = acc && k < num_points_ ? &msg_acc_[6 * k] : nullptr;
    const double *b = a && !first ? &prev_acc_[6 * k] : a;  // b = a: 3 a - b = 2 a
    for (int c = 0; c < 3; ++c) {
      A.x[c] = P.x[c] - T * P.v[c];
      const double dv = a ? 0.5 * T * (3 * a[c] - b[c]) : P.v[c] - Q.v[c];
      const double dw = a ? 0.5 * T * (3 * a[3 + c] - b[3 + c]) : P.w[c] - Q.w[c];
      B.v[c] = P.v[c] + dv;
      B.x[c] = P.x[c] + 0.5 * T * dv;
      B.w[c] = P.w[c] + dw;
      back[c] = -T * P.w[c];
      half[c] = 0.5 * T * dw;
    }
    A.R = mat_mul(math::rotation_of_vector(back), P.R);
    B.R = mat_mul(math::rotation_of_vector(half), P.R);
    poseA_[k] = A;
    poseB_[k] = B;
  }
  prev_msg_ = msg;
  prev_acc_ = msg_acc_;
}

bool FixMBDyn::uses_accelerations() const
{
  // in the global frame only: with a reference node they would be relative to it
  return options_->nodal.accelerations && !options_->nodal.reference_node;
}

void FixMBDyn::read_accelerations(std::vector<double> &out) const
{
  const mb::Kinematics &k = kinematics();
  out.assign(6 * num_points_, 0.0);
  for (std::size_t i = 0; i < num_points_; ++i)
    for (int c = 0; c < 3; ++c) {
      if (k.a.size() == 3 * num_points_) out[6 * i + c] = k.a[3 * i + c];
      if (k.omega_dot.size() == 3 * num_points_) out[6 * i + 3 + c] = k.omega_dot[3 * i + c];
    }
}

void FixMBDyn::setup_pre_exchange()
{
  if (restored_) resume_session();  // the first run after read_restart
  if (ended_) return;
  if (!bound_) {
    open_session();
    const Message m = receive_broadcast("MBDyn's initial (t0) kinematics");
    if (m.status == 1)
      fail_all("MBDyn ended the simulation (sent 5) before sending its initial kinematics");
    decode_to_global(poseA_);
    prev_msg_.clear();
    bind_atoms();
    cur_ = poseA_;
    poseB_ = poseA_;
    t0_answer_pending_ = true;
    mbdyn_step_ = 0;
  }
  apply_pose(cur_, true);
}

void FixMBDyn::setup(int)
{
  profile_.start_run();
  if (!t0_answer_pending_ || ended_) return;
  std::vector<double> loads;
  accumulate_loads(cur_, loads);
  if (tight_ && !startup_exchange_) {
    // MBDyn's derivatives solve did not exchange (zero initial residual, spec T2): this first
    // message is already step 1's prediction; the first LAMMPS step answers it as an iterate.
    prev_avg_ = loads;
    prev_is_t0_ = true;
    t0_answer_pending_ = false;
    first_is_step1_ = true;
    substep_ = 0;
    return;
  }
  // The t0 answer feeds MBDyn's initial derivatives; tight coupling answers it with 6 (spec T1).
  send_answer(loads, true, "the loads for MBDyn's initial state (t0)");
  prev_avg_ = loads;
  prev_is_t0_ = true;
  t0_answer_pending_ = false;
  substep_ = 0;
}

void FixMBDyn::post_integrate()
{
  if (!bound_) return;
  profile_.start_step();
  profile_.begin();
  const PhaseEnd pose_end{profile_, ExchangeProfile::Pose};  // everything after the receive
  if (ended_) {
    apply_pose(cur_, true);
    return;
  }
  if (substep_ == 0) {
    if (first_is_step1_) {
      first_is_step1_ = false;  // poseB_ holds the message received at setup
      mbdyn_step_ = 1;
    } else {
      const Message m = receive_broadcast("MBDyn's kinematics of its next step");
      profile_.lap(ExchangeProfile::Receive);
      if (m.status == 1) {
        stop_run_at_end(m);
        apply_pose(cur_, true);
        return;
      }
      mbdyn_step_ = m.step;
      if (pose_is_message()) {
        decode_to_global(cur_);
        ++substep_;
        apply_pose(cur_, true);
        return;
      }
      decode_to_global(poseB_);
      if (correct_predictor_) {
        msg_ = poseB_;  // a copy: correct_prediction rewrites poseB_ (msg_ keeps its storage)
        if (uses_accelerations()) read_accelerations(msg_acc_);
        correct_prediction(msg_);
      }
    }
    if (substeps_ > 1) std::fill(fsum_.begin(), fsum_.end(), 0.0);  // with 1 sub-step it stays 0
  }
  ++substep_;
  interpolate(static_cast<double>(substep_) / substeps_, cur_);
  apply_pose(cur_, true);
}

bool FixMBDyn::pose_is_message() const
{
  // Loose coupling, one sub-step, MBDyn's own prediction: interpolate would copy the message's
  // pose (B at s = 1), so it is decoded straight into cur_. Only sub-steps, tight iterations and
  // the predictor correction read poseA_ and poseB_.
  return substeps_ == 1 && !tight_ && !correct_predictor_;
}

void FixMBDyn::reevaluate_forces(int vflag)
{
  // Tight iterate: only the forces are re-evaluated, for the coupled atoms at the iterate's
  // pose and every other atom where it is (tight_reevaluation.h). Fixes defined before fix mbdyn
  // get their post_force again; later ones run once, after the iterations.
  in_reeval_ = true;
  reevaluate_forces_for_iterate(lmp, id, vflag, [this]() {
    for (MbdynMeshDriver &m : meshes_) m.restart_totals();  // before the wall fixes add again
    if (deform_) deform_->restart_totals();
  });
  in_reeval_ = false;
}

void FixMBDyn::post_force(int vflag)
{
  if (in_reeval_ || !bound_ || ended_ || substep_ == 0) return;
  profile_.begin();
  const PhaseEnd loads_end{profile_, ExchangeProfile::Loads};
  std::vector<double> &loads = step_loads_;  // reused: no allocation per step
  accumulate_loads(cur_, loads);
  if (substep_ < substeps_) {
    for (std::size_t c = 0; c < loads.size(); ++c) fsum_[c] += loads[c];
    return;
  }
  // Impulse-consistent average over the N sub-steps: F = (1/N) sum_j f(t_{k-1} + j h).
  const double inv = 1.0 / substeps_;
  // With 'loads extrapolate' the average (centred (N-1) h / 2 before t_k) is shifted to t_k
  // with the previous step's average: exact for loads linear in time, impulse kept up to a
  // bounded end term. With N = 1 the average is already the end-of-step load.
  const bool shift = extrapolate_ && substeps_ > 1 && prev_avg_.size() == fsum_.size();
  std::vector<double> &avg = avg_;  // reused: no allocation per step
  auto average = [&](const std::vector<double> &last) -> const std::vector<double> & {
    avg.resize(last.size());
    for (std::size_t c = 0; c < last.size(); ++c) avg[c] = (fsum_[c] + last[c]) * inv;
    // the right-end sub-step average is centred at t_k - (N-1) h / 2; the previous one N h
    // earlier, the t0 loads (N+1) h / 2 earlier
    if (shift)
      for (std::size_t c = 0; c < last.size(); ++c)
        avg[c] += (avg[c] - prev_avg_[c]) * (substeps_ - 1.0) / (prev_is_t0_ ? substeps_ + 1.0 : 2.0 * substeps_);
    return avg;
  };
  auto plain_average = [&](const std::vector<double> &last, std::vector<double> &out) {
    out.resize(last.size());
    for (std::size_t c = 0; c < last.size(); ++c) out[c] = (fsum_[c] + last[c]) * inv;
  };
  // With one sub-step the average, (0 + f) * 1, is f itself to the bit (f is never -0.0: each entry
  // is 0.0 plus a sum, which round-to-nearest never makes -0.0; node meshes write their own entries,
  // so with them the average is still taken).
  const bool average_is_loads = substeps_ == 1 && meshes_.empty() && !deform_;
  if (!tight_) {
    send_answer(average_is_loads ? loads : average(loads), true, "the loads of MBDyn step (loose)");
    last_iterations_ = 1;
  } else {
    int it = 0;
    double change = -1.0;
    for (;;) {
      int converged = (it + 1 >= max_iterations_) || (it > 0 && change <= tolerance_);
      MPI_Bcast(&converged, 1, MPI_INT, 0, world);  // rank 0 decides (spec P5)
      send_answer(average_is_loads ? loads : average(loads), converged != 0,
                  converged ? "the converged loads (tight)" : "the loads of an iterate (tight)");
      if (converged) break;
      profile_.lap(ExchangeProfile::Loads);
      const Message m = receive_broadcast("MBDyn's next iterate (tight)");
      profile_.lap(ExchangeProfile::Receive);
      if (m.status == 1) {
        stop_run_at_end(m);
        return;
      }
      std::vector<Pose> next(nodes_.size());
      decode_to_global(next);
      change = pose_change(poseB_, next);
      poseB_ = next;
      cur_ = next;
      ++it;
      apply_pose(cur_, true);
      reevaluate_forces(vflag);
      accumulate_loads(cur_, loads);
    }
    last_iterations_ = it + 1;
  }
  if (extrapolate_ && substeps_ > 1) plain_average(loads, prev_avg_);  // read only by the shift above
  prev_is_t0_ = false;
  poseA_.swap(poseB_);  // poseB_ is overwritten by the next message before it is read again
  substep_ = 0;
}

void FixMBDyn::end_of_step()
{
  // Integrators must not move coupled atoms; if one did, its velocities are reset here.
  if (!bound_ || !others_move_coupled_) return;
  profile_.begin();
  const PhaseEnd end{profile_, ExchangeProfile::EndOfStep};
  apply_pose(cur_, false);
}

void FixMBDyn::post_run()
{
  if (comm->me == 0 && profile_.enabled()) utils::logmesg(lmp, profile_.summary(where()));
}

double FixMBDyn::compute_vector(int i)
{
  switch (i) {
    case 0: return static_cast<double>(mbdyn_step_);
    case 1: return static_cast<double>(last_iterations_);
    case 2: return static_cast<double>(messages_);
    case 3: return static_cast<double>(substeps_);
  }
  // f_ID[5..]: for each node mesh, where the point attached to its mesh at t0 is now
  const int m = (i - 4) / 3, c = (i - 4) % 3;
  if (m >= 0 && m < static_cast<int>(meshes_.size()) && bound_) return meshes_[m].tracked_point()[c];
  return 0.0;
}

double FixMBDyn::compute_array(int i, int j)
{
  // the last loads sent, global frame
  if (!answer_is_global6() || !answer_) return sent_[6 * i + j];
  return j < 3 ? answer_->force[3 * i + j] : answer_->moment[3 * i + j - 3];
}

bool FixMBDyn::answer_is_global6() const
{
  // no reference node (no rotation into its frame) and moments sent (orientation other than none)
  return !options_->nodal.reference_node && options_->nodal.has_rotation();
}

static void *create_fix_mbdyn(void *lmp, int narg, char **arg)
{
  // `modal FEM-FILE` after the socket: MBDyn's external modal force (fix_mbdyn_modal.h)
  for (int i = 3; i + 1 < narg && i <= 6; ++i)
    if (strcmp(arg[i], "modal") == 0) return new FixMBDynModal(static_cast<LAMMPS *>(lmp), narg, arg);
  return new FixMBDyn(static_cast<LAMMPS *>(lmp), narg, arg);
}
static RegisterStyle reg_fix_mbdyn("fix", "mbdyn", "coupling to MBDyn's external structural force (socket)",
                                   create_fix_mbdyn);

}  // namespace dembridge
