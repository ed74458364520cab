// fix parmec/torsion: LAMMPS glue for the Parmec TORSION_SPRING kernels. See fix_parmec_torsion.h for the
// design and doc/fix_parmec_torsion.md for the user syntax.
#include "fix_parmec_torsion.h"
#include "command_args.h"
#include "definition_file.h"

#include "style_registry.h"

#include "axis_inertia.h"
#include "torsion_step.h"
#include "math/quaternion.h"

#include "atom.h"
#include "comm.h"
#include "domain.h"
#include "error.h"
#include "modify.h"
#include "memory.h"
#include "update.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <sstream>
#include <stdexcept>

using namespace LAMMPS_NS;
using namespace LAMMPS_NS::FixConst;
namespace sp = dembridge::springs;
namespace ts = dembridge::torsion;

namespace dembridge {

using sp::operator-;

namespace {

constexpr int kState = ts::TorsionState::kPackedSize;
constexpr int kTorque = 1 + kState;  // offset of the stored torque in a slot
constexpr int kValid = kTorque + 3;  // 1 once the spring has committed a step
constexpr int kCols = 16;            // id ROLL PITCH YAW TRQTOT_R/P/Y TRQSPR_R/P/Y XDIR_X/Y/Z ZDIR_X/Y/Z
constexpr int kHist = 15;            // history columns per spring
const char *const kAxis[3] = {"roll", "pitch", "yaw"};

const char *const kOptions[] = {"kroll", "kpitch", "kyaw", "droll", "dpitch", "dyaw", "cone", "refpnt"};
const char *const kKeywords[] = {"table", "torsion", "file", "history", "start", "order", "inertia"};

bool is_option(const std::string &s)
{
  for (const char *o : kOptions)
    if (s == o) return true;
  return false;
}

bool is_keyword(const std::string &s)
{
  for (const char *o : kKeywords)
    if (s == o) return true;
  return false;
}

using args::is_number;

// Row-major rotation matrix (body -> space) of a LAMMPS quaternion (w, x, y, z): the spring loops' matrix.
ts::Mat3 rotation(const double *q)
{
  const math::BodyRotation r = math::BodyRotation::of(q);
  return {r.m[0][0], r.m[0][1], r.m[0][2], r.m[1][0], r.m[1][1], r.m[1][2], r.m[2][0], r.m[2][1], r.m[2][2]};
}

sp::Vec3 apply_t(const ts::Mat3 &m, const sp::Vec3 &v) { return math::mat_t_vec(m, v.data()); }

sp::Vec3 vec(const double *a) { return {a[0], a[1], a[2]}; }

}  // namespace

FixParmecTorsion::FixParmecTorsion(LAMMPS *lmp, int narg, char **arg) :
    PerAtomStateFix(lmp, narg, arg, kSlot),
    reader_(lmp, cmd_, state::DefinitionReader::kTable | state::DefinitionReader::kFile |
                           state::DefinitionReader::kHistory | state::DefinitionReader::kStart,
            "torsion spring", "table, torsion, file, history, start, order or inertia"),
    inertia_(lmp, cmd_)
{
  if (narg < 4)
    error->all(FLERR, cmd_ + ": expected definitions (table, torsion, file, history, start) after the style name");

  local_output(kCols);

  reader_.parse(std::vector<std::string>(arg + 3, arg + narg), "command line",
                [this](const std::vector<std::string> &tok, std::size_t &i, const std::string &where) {
                  if (tok[i] == "order") {
                    parmec_order_ = reader_.choice(tok, i, where, {"lammps", "parmec"}) == 1;
                    return true;
                  }
                  if (tok[i] == "inertia") {  // critical-ratio dampers with the bodies' inertia tensors
                    reader_.need(tok, i, 1, "the name of a d2_NAME 6 per-atom property", where);
                    inertia_.set_name(tok[i + 1]);
                    i += 2;
                    return true;
                  }
                  return parse_torsion(tok, i, where);
                });
  resolve();

  reference_frames(snapshot_entity_atoms());
  initial_states();

  open_history(reader_.history, "trq",
               {"ROLL", "PITCH", "YAW", "TRQTOT_R", "TRQTOT_P", "TRQTOT_Y", "TRQSPR_R", "TRQSPR_P", "TRQSPR_Y",
                "XDIR_X", "XDIR_Y", "XDIR_Z", "ZDIR_X", "ZDIR_Y", "ZDIR_Z"});
}

// Resolve table IDs (forward references allowed), validate each law, size the per-atom state.
void FixParmecTorsion::resolve()
{
  std::vector<long> ids;
  std::vector<std::pair<long, long>> atoms;
  for (std::size_t s = 0; s < defs_.size(); s++) {
    TorsionDef &d = defs_[s];
    const LawNames &n = names_[s];
    const std::string who = cmd_ + ": torsion spring " + std::to_string(d.id) + ": ";
    for (int a = 0; a < 3; a++) {
      if (!n.k[a].empty()) d.law.axis[a].spring = reader_.table(n.k[a], who, std::string("k") + kAxis[a]);
      if (!n.d[a].empty()) d.law.axis[a].damper = reader_.table(n.d[a], who, std::string("d") + kAxis[a]);
    }
    try {
      d.law.validate();
    } catch (std::invalid_argument &e) {
      error->all(FLERR, who + e.what());
    }
    ids.push_back(d.id);
    atoms.emplace_back(d.tag1, d.tag2);
  }
  names_.clear();
  define_entities("torsion spring", ids, atoms, 3);  // state on part1; torque (3) on each atom
}

// ---------------------------------------------------------------------------------------------------
// parsing

bool FixParmecTorsion::parse_torsion(const std::vector<std::string> &tok, std::size_t &i, const std::string &where)
{
  if (tok[i] != "torsion") return false;
  // torsion SID I1 I2 zx zy zz xx xy xz [options]
  state::EntityWords w(reader_, tok, i, where, "torsion SID part1 part2 zx zy zz xx xy xz [options]");
  TorsionDef d;
  LawNames n;
  d.id = w.id(ids_);
  d.tag1 = w.part1();
  d.tag2 = w.part2(d.tag1, "anchored in space");
  sp::Vec3 zdir, xdir;
  for (int c = 0; c < 3; c++) zdir[c] = w.number(w.next("zdir component"), "zdir");
  for (int c = 0; c < 3; c++) xdir[c] = w.number(w.next("xdir component"), "xdir");
  w.check([&] { d.input = ts::reference_frame(zdir, xdir); });

  std::vector<std::string> cone;
  bool have_cone = false;
  while (w.more() && is_option(w.peek())) {
    const std::string o = w.next("option");
    int a = -1;
    for (int c = 0; c < 3; c++)
      if (o.substr(1) == kAxis[c]) a = c;
    if (o[0] == 'k' && a >= 0) {
      n.k[a] = w.next(o + " table ID");
      if (is_number(n.k[a])) w.fail(o + ": expected a table ID, got '" + n.k[a] + "'");
    } else if (o[0] == 'd' && a >= 0) {
      const std::string &v = w.next(o + " table ID or critical damping ratio");
      if (is_number(v)) {
        const double z = w.number(v, o + " ratio");
        if (z < 0) w.fail(o + ": critical damping ratio must be >= 0, got " + v);
        d.law.axis[a].ratio = z;
        n.d[a].clear();
      } else {
        n.d[a] = v;
        d.law.axis[a].ratio.reset();
      }
    } else if (o == "cone") {
      have_cone = true;
      cone.clear();
      while (w.more() && !is_option(w.peek()) && !is_keyword(w.peek())) cone.push_back(w.next("cone name"));
    } else if (o == "refpnt") {
      for (int c = 0; c < 3; c++) d.refpnt[c] = w.number(w.next("refpnt component"), "refpnt");
      d.has_refpnt = true;
    }
  }
  if (w.more() && !is_keyword(w.peek()))
    w.fail("unknown option '" + w.peek() + "' (expected kroll, kpitch, kyaw, droll, dpitch, dyaw, cone or refpnt)");
  if (have_cone) {
    if (cone.empty()) w.fail("cone: expected 2 or 3 of roll, pitch, yaw");
    w.check([&] { d.law.cone = ts::parse_cone(cone); });
  }
  defs_.push_back(d);
  names_.push_back(n);
  return w.accept(i);
}

// ---------------------------------------------------------------------------------------------------
// reference frames (kernel doc §5): the input frame expressed in part1's body frame

void FixParmecTorsion::reference_frames(const std::vector<state::AtomSnapshot> &snap)
{
  for (std::size_t s = 0; s < defs_.size(); s++) {
    TorsionDef &d = defs_[s];
    const ts::Mat3 R = rotation(snap[2 * s].q);
    d.body.x = apply_t(R, d.input.x);
    d.body.y = apply_t(R, d.input.y);
    d.body.z = apply_t(R, d.input.z);
  }
}

void FixParmecTorsion::initial_states()
{
  initial_records([](int, double *rec) { ts::TorsionState().pack(rec + 1); });  // angles 0 (fresh state, Q23)
}

// ---------------------------------------------------------------------------------------------------
// run-time checks

void FixParmecTorsion::init()
{
  check_run_style_and_ghosts("torsion springs between two atoms need ghost angular velocities");
  if (!atom->quat_flag || !atom->quat)
    error->all(FLERR, cmd_ + ": torsion springs co-rotate with part1 and need per-atom quaternions: use atom_style "
                             "bpm/sphere with fix nve/bpm/sphere");
  if (!atom->omega_flag || !atom->torque_flag)
    error->all(FLERR, cmd_ + ": needs per-atom angular velocity and torque (atom_style bpm/sphere)");
  for (const TorsionDef &d : defs_)
    if (d.law.needs_axis_inertia() && (!atom->rmass_flag || (!atom->radius_flag && inertia_.name().empty())))
      error->all(FLERR, cmd_ + ": torsion spring " + std::to_string(d.id) +
                            ": a critical damping ratio needs per-atom mass and an inertia ('inertia NAME' or the "
                            "sphere's 0.4 m r^2 from the radius)");
  inertia_.rows();  // ERROR now if 'inertia NAME' names no d2_ property of 6 columns
  check_record_count();
  rigid_ = nullptr;
  if (parmec_order_) {
    const auto rigid = modify->get_fix_by_style("^parmec/rigid$");
    if (rigid.empty())
      error->all(FLERR, cmd_ + ": order parmec: needs fix parmec/rigid (the springs co-rotate with the rotations it "
                               "keeps)");
    rigid_ = rigid.front();
  }
}

// Any distance between the atoms: the layer keeps the ghost cutoff above it (setup_pre_exchange, pre_exchange).
void FixParmecTorsion::setup(int)
{
  evaluate(Mode::Setup);
}

// One evaluation of every torsion spring owned here. Commit: advance the state (once per step). Trial:
// on a copy. Setup: re-apply the torque of the last committed step (split runs and restarts continue
// bitwise); before any committed step a trial torque ('start lammps') or none ('start parmec').
void FixParmecTorsion::evaluate(Mode mode)
{
  const int nlocal = atom->nlocal;
  reset_sums();

  double **omega = atom->omega;
  double **quat = atom->quat;
  const double *rmass = atom->rmass_flag ? atom->rmass : nullptr;
  const double dt = update->dt;

  local_rows(static_cast<int>(records_.total(nlocal)));
  int row = 0;
  double **x = atom->x;
  const double near2 = near_length() * near_length();
  bool near = false;  // a pair near the ghost cutoff (the layer then checks their reach)

  // 'order parmec': Parmec's stored rotation Λ (fix parmec/rigid, local and ghost atoms; with Q3 it is not
  // orthogonal), otherwise the atom quaternion's
  double **rot = rigid_ ? rigid_->array_atom : nullptr;
  auto rotation_of = [&](int i) -> ts::Mat3 {
    if (!rot) return rotation(quat[i]);
    ts::Mat3 m;
    std::copy(rot[i], rot[i] + 9, m.begin());
    return m;
  };
  // referential J⁻¹ of a body (spec §7): the 'inertia NAME' tensor, else the sphere's
  auto inv_inertia = [&](int i) -> ts::Mat3 { return inertia_.inverse(i, rmass ? rmass[i] : 0.0); };

  for (int i = 0; i < nlocal; i++) {
    for (int s = 0; s < records_.count(i); s++) {
      double *slot = records_.record(i, s);
      const int idx = records_.key(i, s);
      const TorsionDef &d = defs_[idx];
      const int k = d.tag2 >= 0 ? second_atom(idx, i, false) : -1;
      if (k >= 0) {
        const double dx = x[k][0] - x[i][0], dy = x[k][1] - x[i][1], dz = x[k][2] - x[i][2];
        near = near || dx * dx + dy * dy + dz * dz > near2;
      }
      ts::TorsionState state;
      state.unpack(slot + 1);
      double t[3] = {0.0, 0.0, 0.0};
      bool apply = true;
      if (mode == Mode::Setup && slot[kValid] != 0.0) {
        for (int c = 0; c < 3; c++) t[c] = slot[kTorque + c];
      } else if (mode == Mode::Setup && reader_.parmec_start) {
        apply = false;
      } else {
        const ts::Mat3 L1 = rotation_of(i);
        ts::TorsionStepInput in;
        in.frame = ts::current_frame(d.body, L1);
        in.relative_omega = vec(omega[i]);
        if (k >= 0) in.relative_omega = in.relative_omega - vec(omega[k]);
        in.dt = dt;
        if (d.law.needs_axis_inertia() && rot) {  // Parmec's R (J1⁻¹ + J2⁻¹) Rᵀ
          const ts::Mat3 J2 = k >= 0 ? inv_inertia(k) : ts::Mat3{};
          in.axis_inertia = ts::axis_inertias_parmec(in.frame, inv_inertia(i), k >= 0 ? &J2 : nullptr);
        } else if (d.law.needs_axis_inertia()) {
          const ts::Mat3 W1 = ts::spatial_inverse_inertia(L1, inv_inertia(i));
          if (k >= 0) {
            const ts::Mat3 W2 = ts::spatial_inverse_inertia(rotation_of(k), inv_inertia(k));
            in.axis_inertia = ts::axis_inertias(in.frame, W1, &W2);
          } else {
            in.axis_inertia = ts::axis_inertias(in.frame, W1, nullptr);
          }
        }
        const ts::TorsionTorque tq = ts::advance_torsion(d.law, state, in);
        for (int c = 0; c < 3; c++) t[c] = tq.on_part1[c];
        if (mode == Mode::Commit) {
          state.pack(slot + 1);
          for (int c = 0; c < 3; c++) slot[kTorque + c] = t[c];
          slot[kValid] = 1.0;
        }
      }
      if (apply) {
        contribute(i, idx, t, 1.0);
        if (k >= 0) contribute(k, idx, t, -1.0);
      }
      double *out = array_local[row++];
      out[0] = static_cast<double>(d.id);
      for (int c = 0; c < 3; c++) {
        out[1 + c] = state.angle[c];
        out[4 + c] = state.torque_total[c];
        out[7 + c] = state.torque_spring[c];
        out[10 + c] = state.xdir[c];
        out[13 + c] = state.zdir[c];
      }
    }
  }

  if (near) note_near();
  collect_sums();

  // Each atom's contributions summed in spring order: the result does not depend on the decomposition.
  double **torque = atom->torque;
  double sum[3];
  for (int i = 0; i < nlocal; i++) {
    if (sums_.empty(i)) continue;
    sums_.sum(i, sum);
    for (int c = 0; c < 3; c++) torque[i][c] += sum[c];
  }
}

// History columns of one torsion spring: the first kHist values of its state (angles, torques, axes).
void FixParmecTorsion::history_values(const double *rec, double *out) const
{
  std::copy(rec + 1, rec + 1 + kHist, out);
}

// Global restart: the body-frame reference directions, so that a restarted run does not re-reference the
// springs to the current orientations.
void FixParmecTorsion::write_restart(FILE *fp)
{
  write_entity_restart(fp, 9, 1.0, [this](int s, double *o) {
    for (int c = 0; c < 3; c++) {
      o[c] = defs_[s].body.x[c];
      o[3 + c] = defs_[s].body.y[c];
      o[6 + c] = defs_[s].body.z[c];
    }
  });
}

void FixParmecTorsion::restart(char *buf)
{
  read_entity_restart(buf, [](bool) { return 9; }, [this](int s, const double *o, int) {
    for (int c = 0; c < 3; c++) {
      defs_[s].body.x[c] = o[c];
      defs_[s].body.y[c] = o[3 + c];
      defs_[s].body.z[c] = o[6 + c];
    }
  });
}

static RegisterStyle reg_fix_parmec_torsion("fix", "parmec/torsion",
                                            "Parmec TORSION_SPRING: roll/pitch/yaw tables, dampers, cone limits",
                                            create_fix<FixParmecTorsion>);

}  // namespace dembridge
