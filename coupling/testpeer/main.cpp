// mbdyn_testpeer: plays MBDyn's `external structural` side so Python/LAMMPS tests can run a
// coupling without MBDyn. Exit status as MBDyn's: 0 completed, 1 error, 2 interrupted.
#include <cerrno>
#include <climits>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <iostream>
#include <sstream>
#include <string>
#include <utility>

#include "mbdyn_test_peer.h"
#include "free_bodies_peer.h"
#include "free_modal_body_peer.h"
#include "modal_fem_file.h"
#include "modal_peer.h"
#include "mapping_peer.h"

using namespace dembridge::mbdyn::testpeer;

namespace {

const char* kUsage =
    "usage: mbdyn_testpeer (--path FILE | --port N [--host H]) [options]\n"
    "  --create yes|no          yes (default): listen like MBDyn `create, yes`; no: connect\n"
    "  --nodes N                number of points (default 1)\n"
    "  --orientation none|vector|matrix|euler123   (default matrix, MBDyn's default)\n"
    "  --labels  --accelerations  --reference-node\n"
    "  --coupling loose|tight|none   (default loose)\n"
    "  --steps K (default 10)   --dt DT (default 1e-3)\n"
    "  --mass M  --inertia J  --gravity gx,gy,gz\n"
    "  --x0 x,y,z  --v0 vx,vy,vz   initial state of the next node (repeat per node)\n"
    "  --spin0 theta,theta_dot  initial spin angle and rate of the next node (repeat per node)\n"
    "  --tilt T                 constant tilt about x of every node (default 0.3 (i+1) rad)\n"
    "  --offset ox,oy,oz        offset of the next node's point, node frame (repeat per node)\n"
    "  --force fx,fy,fz         constant absolute force on every node (MBDyn `force`)\n"
    "  --spin-axis ax,ay,az     global axis of every node's spin (default 0,0,1)\n"
    "  --hinge k,c,cx,cy,cz     revolute hinge at the node: no translation, a torsion spring k and\n"
    "                           damper c about the spin axis, centre of mass at c (node frame) under\n"
    "                           --gravity; --inertia is then the moment of inertia about the hinge\n"
    "  --method cn|ms [--rho R]  MBDyn's `method`: crank nicolson (default) or `ms, R` (R default 0.6;\n"
    "                           not with --hinge)\n"
    "  --max-iterations N (20)  --derivatives-max-iterations N (10)\n"
    "  --tolerance T (1e-9)  --derivatives-tolerance T (1e-6)  --derivatives-coefficient C (1e-6)\n"
    "  --accept-timeout S  --io-timeout S   (default 30 each; <= 0 waits forever like MBDyn)\n"
    "  --fault none|garbage-command|short-then-close|short-then-stall|nan|die  --fault-message K\n"
    "  --trajectory FILE        write t, then per node x y z vx vy vz theta theta_dot\n"
    "  --file-in IN --file-out OUT [--file-precision P (16)]   MBDyn's file communicator instead of the\n"
    "                           socket (loose, send after predict no; orientation none or matrix)\n"
    "  --modal-mass m1,...,mM --modal-stiffness k1,... --modal-damping c1,... [--modal-q0 q1,...]\n"
    "                           MBDyn's `external modal, type, modal` on a clamped modal node instead:\n"
    "                           M q'' + C q' + K q = p per mode (--path, --steps, --dt, --trajectory:\n"
    "                           t, then q, q', q'', p per mode; --coupling loose|tight, --loads-log: index,\n"
    "                           command, p; --max-iterations; --save-state, --resume)\n"
    "  --reference-body m,J,x,y,z,vx,vy,vz,wx,wy,wz  --point-body m,J,x,...,wz (repeat per point)\n"
    "  [--reference-label L (10)] [--point-labels l1,l2,...]\n"
    "                           `external structural` with `reference node` on free rigid bodies instead\n"
    "                           (MBDyn dynamic nodes with a body of isotropic inertia J each; labels, sorted\n"
    "                           no, orientation matrix, use/rotate reference node forces yes; with\n"
    "                           --path, --steps, --dt, --gravity, --trajectory: t, then per body, reference\n"
    "                           first, x R(row by row) v w)\n"
    "  --modal-fem FILE [--modal-origin LABEL] [--modal-node x,y,z,vx,vy,vz,wx,wy,wz]\n"
    "  [--modal-initial q1,q'1,q2,q'2,...]\n"
    "                           `external modal, type, all` on a free modal body instead: MBDyn's `modal`\n"
    "                           joint (that FEM file, no interface nodes, `origin node` LABEL) on a modal\n"
    "                           node starting at x with R = I, v, w (with --path, --coupling, --steps, --dt,\n"
    "                           --tolerance, --max-iterations, --trajectory: t, x R(row by row) v w, then\n"
    "                           q q' q'' per mode)\n"
    "  --cantilever n,L,m,J,EA,GA,GJ,EI --beam-offset ox,oy,oz (repeat) --mapping FILE --mapped-points M\n"
    "                           `external structural mapping` on a cantilever of n beam2 elements along x\n"
    "                           (length L, node 0 static and clamped at the origin, a body m, diag(J) on\n"
    "                           every other node, `linear elastic generic, diag, EA, GA, GA, GJ, EI, EI`),\n"
    "                           every node carrying the offset points, mapped by MBDyn's sparse mapping\n"
    "                           file to M points (with --path, --steps, --dt, --gravity, --coupling,\n"
    "                           --tolerance, --trajectory: t, then per node x R(row by row) v w)\n"
    "  --kinematics-log FILE    one line per kinematics message: index, command, then per point\n"
    "                           x(3) R(9, row by row) v(3) w(3), global frame\n"
    "  --loads-log FILE         one line per loads answer: index, command, then per point the force\n"
    "                           (and moment) as received (then the reference record's, if any)\n"
    "  --save-state FILE        at the end, the state after the last step solved with the peer's loads\n"
    "  --resume FILE            continue from such a state (socket, loose or tight): no start-up\n"
    "                           exchange, the first message is the next step's (--steps: the last step)\n";

// Status 2, as a command-line tool's usage error; never an uncaught exception (abort, 134).
[[noreturn]] void usage_error(const std::string& why) {
  std::cerr << "mbdyn_testpeer: " << why << "\n" << kUsage;
  std::exit(2);
}

// The whole text must be the number: "abc", "3x", "" and out-of-range values are usage errors.
double parse_double(const std::string& option, const std::string& text) {
  char* end = nullptr;
  errno = 0;
  const double v = std::strtod(text.c_str(), &end);
  if (text.empty() || *end != '\0' || errno == ERANGE || !std::isfinite(v))
    usage_error(option + " expects a finite number, got '" + text + "'");
  return v;
}

long parse_integer(const std::string& option, const std::string& text, long lo, long hi) {
  char* end = nullptr;
  errno = 0;
  const long v = std::strtol(text.c_str(), &end, 10);
  if (text.empty() || *end != '\0' || errno == ERANGE || v < lo || v > hi)
    usage_error(option + " expects an integer from " + std::to_string(lo) + " to " + std::to_string(hi) + ", got '" +
                text + "'");
  return v;
}

V3 parse_v3(const std::string& s) {
  V3 v{};
  char c1, c2;
  std::istringstream in(s);
  if (!(in >> v[0] >> c1 >> v[1] >> c2 >> v[2]) || c1 != ',' || c2 != ',') usage_error("expected x,y,z, got '" + s + "'");
  return v;
}

std::vector<double> parse_list(const std::string& option, const std::string& text) {
  std::vector<double> v;
  std::string item;
  std::istringstream in(text);
  while (std::getline(in, item, ',')) v.push_back(parse_double(option, item));
  if (v.empty()) usage_error(option + " expects a comma-separated list of numbers");
  return v;
}

int run_modal(const PeerSetup& s, ModalPeerSetup m, const std::string& trajectory_file) {
  const std::size_t n = m.mass.size();
  if (m.stiffness.size() != n || m.damping.size() != n || (!m.q0.empty() && m.q0.size() != n))
    usage_error("--modal-mass, --modal-stiffness, --modal-damping and --modal-q0 need one value per mode");
  for (double mass : m.mass)
    if (!(mass > 0)) usage_error("--modal-mass expects positive modal masses");
  if (s.place.unix_path.empty()) usage_error("the modal peer needs --path");
  if (s.coupling == CouplingMode::None) usage_error("the modal body is loose or tight");
  m.place = s.place;
  m.tight = s.coupling == CouplingMode::Tight;
  m.max_iterations = s.max_iterations;
  m.save_state = s.save_state;
  m.resume_state = s.resume_state;
  m.loads_log = s.loads_log;
  m.steps = s.steps;
  m.dt = s.dt;
  m.accept_timeout_s = s.accept_timeout_s;
  m.io_timeout_s = s.io_timeout_s;
  const std::string path = m.place.unix_path;
  m.on_listening = [path]() {
    std::cout << "mbdyn_testpeer: listening on unix socket " << path << " (external modal, type modal)" << std::endl;
  };
  const ModalPeerOutcome out = run_modal_test_peer(m);
  if (!trajectory_file.empty()) {
    std::ofstream f(trajectory_file);
    f.precision(17);
    f << "# t, then q (per mode), q', q'', p (the generalized forces the step was solved with)\n";
    for (const ModalSample& r : out.trajectory) {
      f << r.t;
      for (const auto* v : {&r.q, &r.qdot, &r.qddot, &r.p})
        for (double x : *v) f << ' ' << x;
      f << '\n';
    }
  }
  std::cout << "mbdyn_testpeer: exit " << out.exit_status << ": " << out.log << " (" << out.kinematics_sent
            << " kinematics messages, " << (out.trajectory.empty() ? 0 : out.trajectory.size() - 1) << " steps)"
            << std::endl;
  return out.exit_status;
}

FreeBody parse_body(const std::string& option, const std::string& text) {
  const std::vector<double> v = parse_list(option, text);
  if (v.size() != 11 || !(v[0] > 0) || !(v[1] > 0))
    usage_error(option + " expects m,J,x,y,z,vx,vy,vz,wx,wy,wz with m, J > 0, got '" + text + "'");
  FreeBody b;
  b.mass = v[0];
  b.inertia = v[1];
  for (int k = 0; k < 3; ++k) {
    b.x[k] = v[2 + k];
    b.v[k] = v[5 + k];
    b.w[k] = v[8 + k];
  }
  return b;
}

int run_free_bodies(const PeerSetup& s, FreeBodiesPeerSetup f, const std::vector<double>& labels,
                    const std::string& trajectory_file) {
  if (f.points.empty()) usage_error("--reference-body needs at least one --point-body");
  if (s.place.unix_path.empty()) usage_error("the free-bodies peer needs --path");
  if (s.coupling == CouplingMode::None) usage_error("the free-bodies peer is loose or tight");
  f.tight = s.coupling == CouplingMode::Tight;
  f.max_iterations = s.max_iterations;
  if (labels.empty())
    for (std::size_t i = 0; i < f.points.size(); ++i) f.labels.push_back(static_cast<std::uint32_t>(20 + 10 * i));
  for (double l : labels) {
    if (!(l >= 0 && l <= 4294967295.0) || l != std::floor(l)) usage_error("--point-labels expects unsigned integers");
    f.labels.push_back(static_cast<std::uint32_t>(l));
  }
  if (f.labels.size() != f.points.size()) usage_error("--point-labels needs one label per --point-body");
  f.place = s.place;
  f.steps = s.steps;
  f.dt = s.dt;
  f.gravity = s.model.gravity;
  f.derivatives_coefficient = s.model.derivatives_coefficient;
  f.tolerance = s.tolerance;
  f.accept_timeout_s = s.accept_timeout_s;
  f.io_timeout_s = s.io_timeout_s;
  f.trajectory = trajectory_file;
  const std::string path = f.place.unix_path;
  f.on_listening = [path]() {
    std::cout << "mbdyn_testpeer: listening on unix socket " << path << " (free bodies, reference node)" << std::endl;
  };
  const FreeBodiesPeerOutcome out = run_free_bodies_test_peer(f);
  std::cout << "mbdyn_testpeer: exit " << out.exit_status << ": " << out.log << " (" << out.kinematics_sent
            << " kinematics messages)" << std::endl;
  return out.exit_status;
}

int run_free_modal(const PeerSetup& s, FreeModalBodyPeerSetup f, const std::string& fem_path,
                   const std::string& origin, const std::vector<double>& node, const std::vector<double>& initial,
                   const std::string& trajectory_file) {
  if (s.place.unix_path.empty()) usage_error("the free modal body peer needs --path");
  if (s.coupling == CouplingMode::None) usage_error("the free modal body peer is loose or tight");
  try {
    f.fem = read_modal_fem_file(fem_path);
  } catch (const std::exception& e) {
    usage_error(std::string("--modal-fem: ") + e.what());
  }
  if (!origin.empty()) {
    for (std::size_t i = 0; i < f.fem.labels.size(); ++i)
      if (f.fem.labels[i] == origin) f.origin = static_cast<int>(i);
    if (f.origin < 0) usage_error("--modal-origin: FEM node \"" + origin + "\" is not in " + fem_path);
  }
  if (!node.empty()) {
    if (node.size() != 9) usage_error("--modal-node expects x,y,z,vx,vy,vz,wx,wy,wz");
    for (int k = 0; k < 3; ++k) {
      f.x0[k] = node[k];
      f.v0[k] = node[3 + k];
      f.w0[k] = node[6 + k];
    }
  }
  if (!initial.empty()) {
    if (initial.size() != 2 * f.fem.modes()) usage_error("--modal-initial expects q, q' for each mode of the FEM file");
    for (std::size_t j = 0; j < f.fem.modes(); ++j) {
      f.q0.push_back(initial[2 * j]);
      f.qdot0.push_back(initial[2 * j + 1]);
    }
  }
  f.place = s.place;
  f.tight = s.coupling == CouplingMode::Tight;
  f.max_iterations = s.max_iterations;
  f.tolerance = s.tolerance;
  f.steps = s.steps;
  f.dt = s.dt;
  f.accept_timeout_s = s.accept_timeout_s;
  f.io_timeout_s = s.io_timeout_s;
  f.trajectory = trajectory_file;
  const std::string path = f.place.unix_path;
  f.on_listening = [path]() {
    std::cout << "mbdyn_testpeer: listening on unix socket " << path << " (external modal, free modal body)"
              << std::endl;
  };
  const FreeModalBodyPeerOutcome out = run_free_modal_body_test_peer(f);
  std::cout << "mbdyn_testpeer: exit " << out.exit_status << ": " << out.log << " (" << out.kinematics_sent
            << " kinematics messages)" << std::endl;
  return out.exit_status;
}

int run_mapping(const PeerSetup& s, const std::vector<double>& cantilever, MappingPeerSetup m,
                const std::string& mapping_file, const std::string& trajectory_file) {
  if (cantilever.size() != 8 || cantilever[0] < 1 || cantilever[0] != std::floor(cantilever[0]) ||
      cantilever[0] > 1000 || !(cantilever[1] > 0) || !(cantilever[2] > 0) || !(cantilever[3] > 0))
    usage_error("--cantilever expects n,L,m,J,EA,GA,GJ,EI with n a whole number of elements, L, m, J > 0");
  if (m.offsets.empty()) usage_error("--cantilever needs at least one --beam-offset");
  if (mapping_file.empty() || m.mapped_points < 1) usage_error("--cantilever needs --mapping FILE and --mapped-points M");
  if (s.place.unix_path.empty()) usage_error("the mapping peer needs --path");
  if (s.coupling == CouplingMode::None) usage_error("the mapping peer is loose or tight");
  const int n = static_cast<int>(cantilever[0]);
  for (int k = 0; k <= n; ++k) m.model.node_x.push_back(V3{cantilever[1] * k / n, 0, 0});
  m.model.mass = cantilever[2];
  m.model.inertia = cantilever[3];
  m.model.stiffness = {cantilever[4], cantilever[5], cantilever[5], cantilever[6], cantilever[7], cantilever[7]};
  m.model.gravity = s.model.gravity;
  m.model.derivatives_coefficient = s.model.derivatives_coefficient;
  m.model.derivatives_tolerance = s.derivatives_tolerance;
  m.model.tolerance = s.tolerance;
  try {
    m.mapping = read_sparse_mapping(mapping_file, 3 * m.mapped_points,
                                    3 * (n + 1) * static_cast<int>(m.offsets.size()));
  } catch (const std::exception& e) {
    usage_error(std::string("--mapping: ") + e.what());
  }
  m.place = s.place;
  m.tight = s.coupling == CouplingMode::Tight;
  m.tolerance = s.tolerance;
  m.max_iterations = s.max_iterations;
  m.derivatives_max_iterations = s.derivatives_max_iterations;
  m.steps = s.steps;
  m.dt = s.dt;
  m.accept_timeout_s = s.accept_timeout_s;
  m.io_timeout_s = s.io_timeout_s;
  m.trajectory = trajectory_file;
  const std::string path = m.place.unix_path;
  m.on_listening = [path]() {
    std::cout << "mbdyn_testpeer: listening on unix socket " << path << " (external structural mapping, cantilever)"
              << std::endl;
  };
  const MappingPeerOutcome out = run_mapping_test_peer(m);
  std::cout << "mbdyn_testpeer: exit " << out.exit_status << ": " << out.log << " (" << out.kinematics_sent
            << " kinematics messages)" << std::endl;
  return out.exit_status;
}

}  // namespace

int main(int argc, char** argv) {
  PeerSetup s;
  s.accept_timeout_s = 30;
  s.io_timeout_s = 30;
  std::string trajectory_file;
  std::vector<V3> x0, v0;
  std::vector<std::pair<double, double>> spin0;
  double tilt = -1e300;
  ModalPeerSetup modal;
  FreeBodiesPeerSetup free_bodies;
  bool have_reference_body = false;
  std::vector<double> point_labels;
  FreeModalBodyPeerSetup free_modal;
  std::string modal_fem, modal_origin;
  std::vector<double> modal_node, modal_initial;
  std::vector<double> cantilever;
  MappingPeerSetup mapping;
  std::string mapping_file;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    auto value = [&]() -> std::string {
      if (i + 1 >= argc) usage_error("missing value after " + a);
      return argv[++i];
    };
    if (a == "--path") s.place.unix_path = value();
    else if (a == "--port") s.place.tcp_port = static_cast<int>(parse_integer(a, value(), 0, 65535));
    else if (a == "--host") s.place.host = value();
    else if (a == "--create") s.mbdyn_creates_socket = value() != "no";
    else if (a == "--nodes") s.shape.nodes = static_cast<std::uint32_t>(parse_integer(a, value(), 1, 1000000));
    else if (a == "--orientation") {
      const std::string o = value();
      if (o == "none") s.shape.orientation = Orientation::None;
      else if (o == "vector") s.shape.orientation = Orientation::Vector;
      else if (o == "matrix") s.shape.orientation = Orientation::Matrix;
      else if (o == "euler123") s.shape.orientation = Orientation::Euler123;
      else usage_error("unknown orientation " + o);
    } else if (a == "--labels") s.shape.labels = true;
    else if (a == "--accelerations") s.shape.accelerations = true;
    else if (a == "--reference-node") s.shape.reference_node = true;
    else if (a == "--coupling") {
      const std::string c = value();
      if (c == "loose") s.coupling = CouplingMode::Loose;
      else if (c == "tight") s.coupling = CouplingMode::Tight;
      else if (c == "none") s.coupling = CouplingMode::None;
      else usage_error("unknown coupling " + c);
    } else if (a == "--steps") s.steps = static_cast<int>(parse_integer(a, value(), 0, INT_MAX));
    else if (a == "--dt") s.dt = parse_double(a, value());
    else if (a == "--mass") s.model.mass = parse_double(a, value());
    else if (a == "--inertia") s.model.inertia = parse_double(a, value());
    else if (a == "--gravity") s.model.gravity = parse_v3(value());
    else if (a == "--x0") x0.push_back(parse_v3(value()));
    else if (a == "--v0") v0.push_back(parse_v3(value()));
    else if (a == "--offset") s.model.offset.push_back(parse_v3(value()));
    else if (a == "--force") s.model.force = parse_v3(value());
    else if (a == "--spin0") {
      double th, thd;
      char sep;
      std::istringstream in(value());
      if (!(in >> th >> sep >> thd) || sep != ',') usage_error("--spin0 expects theta,theta_dot");
      spin0.emplace_back(th, thd);
    } else if (a == "--tilt") tilt = parse_double(a, value());
    else if (a == "--spin-axis") s.model.spin_axis = parse_v3(value());
    else if (a == "--hinge") {
      double h[5];
      char sep;
      std::istringstream in(value());
      for (int k = 0; k < 5; ++k)
        if (!(in >> h[k]) || (k < 4 && !(in >> sep))) usage_error("--hinge expects k,c,cx,cy,cz");
      s.model.hinged = true;
      s.model.torsion_stiffness = h[0];
      s.model.torsion_damping = h[1];
      s.model.cm_offset = {h[2], h[3], h[4]};
    }
    else if (a == "--method") {
      const std::string m = value();
      if (m == "cn") s.model.multistep = false;
      else if (m == "ms") s.model.multistep = true;
      else usage_error("--method expects cn or ms, got '" + m + "'");
    } else if (a == "--rho") s.model.rho = parse_double(a, value());
    else if (a == "--tolerance") s.tolerance = parse_double(a, value());
    else if (a == "--derivatives-tolerance") s.derivatives_tolerance = parse_double(a, value());
    else if (a == "--derivatives-coefficient") s.model.derivatives_coefficient = parse_double(a, value());
    else if (a == "--max-iterations") s.max_iterations = static_cast<int>(parse_integer(a, value(), 0, INT_MAX));
    else if (a == "--derivatives-max-iterations") s.derivatives_max_iterations = static_cast<int>(parse_integer(a, value(), 0, INT_MAX));
    else if (a == "--accept-timeout") s.accept_timeout_s = parse_double(a, value());
    else if (a == "--io-timeout") s.io_timeout_s = parse_double(a, value());
    else if (a == "--fault") {
      const std::string f = value();
      if (f == "none") s.fault = Fault::None;
      else if (f == "garbage-command") s.fault = Fault::GarbageCommand;
      else if (f == "short-then-close") s.fault = Fault::ShortPayloadThenClose;
      else if (f == "short-then-stall") s.fault = Fault::ShortPayloadThenStall;
      else if (f == "nan") s.fault = Fault::NanInKinematics;
      else if (f == "die") s.fault = Fault::DieMidRun;
      else usage_error("unknown fault " + f);
    } else if (a == "--fault-message") s.fault_message = static_cast<int>(parse_integer(a, value(), 0, INT_MAX));
    else if (a == "--trajectory") trajectory_file = value();
    else if (a == "--modal-mass") modal.mass = parse_list(a, value());
    else if (a == "--modal-stiffness") modal.stiffness = parse_list(a, value());
    else if (a == "--modal-damping") modal.damping = parse_list(a, value());
    else if (a == "--modal-q0") modal.q0 = parse_list(a, value());
    else if (a == "--kinematics-log") s.kinematics_log = value();
    else if (a == "--modal-fem") modal_fem = value();
    else if (a == "--modal-origin") modal_origin = value();
    else if (a == "--modal-node") modal_node = parse_list(a, value());
    else if (a == "--modal-initial") modal_initial = parse_list(a, value());
    else if (a == "--reference-body") {
      free_bodies.reference = parse_body(a, value());
      have_reference_body = true;
    } else if (a == "--point-body") free_bodies.points.push_back(parse_body(a, value()));
    else if (a == "--reference-label")
      free_bodies.reference_label = static_cast<std::uint32_t>(parse_integer(a, value(), 0, 4294967295L));
    else if (a == "--point-labels") point_labels = parse_list(a, value());
    else if (a == "--loads-log") s.loads_log = value();
    else if (a == "--cantilever") cantilever = parse_list(a, value());
    else if (a == "--beam-offset") mapping.offsets.push_back(parse_v3(value()));
    else if (a == "--mapping") mapping_file = value();
    else if (a == "--mapped-points") mapping.mapped_points = static_cast<int>(parse_integer(a, value(), 1, 1000000));
    else if (a == "--save-state") s.save_state = value();
    else if (a == "--resume") s.resume_state = value();
    else if (a == "--file-in") s.files.in_path = value();
    else if (a == "--file-out") s.files.out_path = value();
    else if (a == "--file-precision") s.files.precision = static_cast<int>(parse_integer(a, value(), 1, 17));
    else if (a == "--help" || a == "-h") {
      std::cout << kUsage;
      return 0;
    } else usage_error("unknown option " + a);
  }
  const bool files = !s.files.in_path.empty() || !s.files.out_path.empty();
  const bool modal_body = !modal.mass.empty() || !modal.stiffness.empty();
  if ((!s.resume_state.empty() || !s.save_state.empty()) &&
      (files || !modal_fem.empty() || !cantilever.empty() || have_reference_body || !free_bodies.points.empty() ||
       s.coupling == CouplingMode::None))
    usage_error("--save-state and --resume are for the oscillator nodes or the --modal-mass body over the socket, "
                "coupling loose or tight");
  if (modal_fem.empty() && (!modal_origin.empty() || !modal_node.empty() || !modal_initial.empty()))
    usage_error("--modal-origin, --modal-node and --modal-initial need --modal-fem");
  if (!modal_fem.empty()) {
    if (modal_body || have_reference_body || !free_bodies.points.empty() || files)
      usage_error("--modal-fem is a peer of its own (not with --modal-mass, --reference-body or --file-in)");
    return run_free_modal(s, free_modal, modal_fem, modal_origin, modal_node, modal_initial, trajectory_file);
  }
  if (modal_body) return run_modal(s, modal, trajectory_file);
  if (!cantilever.empty() || !mapping.offsets.empty() || !mapping_file.empty()) {
    if (cantilever.empty()) usage_error("--beam-offset and --mapping need --cantilever");
    return run_mapping(s, cantilever, mapping, mapping_file, trajectory_file);
  }
  if (have_reference_body || !free_bodies.points.empty()) {
    if (!have_reference_body) usage_error("--point-body needs --reference-body");
    return run_free_bodies(s, free_bodies, point_labels, trajectory_file);
  }
  if (files && (s.files.in_path.empty() || s.files.out_path.empty())) usage_error("give both --file-in and --file-out");
  if (files && (s.coupling != CouplingMode::Loose || s.shape.reference_node || s.shape.accelerations ||
                (s.shape.orientation != Orientation::None && s.shape.orientation != Orientation::Matrix)))
    usage_error("the file communicator is loose, without reference node or accelerations, orientation none or matrix");
  s.files.timeout_s = s.io_timeout_s > 0 ? s.io_timeout_s : 1e9;
  if (!files && s.place.unix_path.empty() && s.place.tcp_port < 0) usage_error("give --path or --port");
  if (s.model.multistep && s.model.hinged) usage_error("--method ms does not integrate a --hinge body");
  if (s.model.rho < 0 || s.model.rho > 1) usage_error("--rho expects a spectral radius from 0 to 1");
  if (s.place.tcp_port >= 0 && s.place.tcp_port != 0 && s.place.tcp_port <= 5000)
    usage_error("MBDyn only accepts ports above 5000 (IPPORT_USERRESERVED)");

  s.model.initial = default_initial_states(s.shape.nodes);
  for (std::size_t i = 0; i < x0.size() && i < s.model.initial.size(); ++i) s.model.initial[i].x = x0[i];
  for (std::size_t i = 0; i < v0.size() && i < s.model.initial.size(); ++i) s.model.initial[i].v = v0[i];
  for (std::size_t i = 0; i < spin0.size() && i < s.model.initial.size(); ++i) {
    s.model.initial[i].theta = spin0[i].first;
    s.model.initial[i].theta_dot = spin0[i].second;
  }
  if (tilt > -1e300) s.model.tilt.assign(s.shape.nodes, tilt);
  const std::string unix_path = s.place.unix_path;
  s.on_listening = [unix_path](int port) {
    // A launcher may wait for this line instead of retrying its connect.
    if (port >= 0)
      std::cout << "mbdyn_testpeer: listening on port " << port << std::endl;
    else
      std::cout << "mbdyn_testpeer: listening on unix socket " << unix_path << std::endl;
  };

  const PeerOutcome out = run_mbdyn_test_peer(s);

  if (!trajectory_file.empty()) {
    std::ofstream f(trajectory_file);
    f.precision(17);
    f << "# t, then per node: x y z vx vy vz theta theta_dot\n";
    for (const PeerSample& p : out.trajectory) {
      f << p.t;
      for (const BodyState& b : p.bodies)
        f << ' ' << b.x[0] << ' ' << b.x[1] << ' ' << b.x[2] << ' ' << b.v[0] << ' ' << b.v[1] << ' '
          << b.v[2] << ' ' << b.theta << ' ' << b.theta_dot;
      f << '\n';
    }
  }
  std::cout << "mbdyn_testpeer: exit " << out.exit_status << ": " << out.log << " ("
            << out.kinematics_sent << " kinematics messages, " << out.answers.size() << " answers, "
            << (out.trajectory.empty() ? 0 : out.trajectory.size() - 1) << " steps)" << std::endl;
  return out.exit_status;
}
