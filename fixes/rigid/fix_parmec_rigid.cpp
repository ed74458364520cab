// fix parmec/rigid: see fix_parmec_rigid.h and doc/fix_parmec_rigid.md.
#include "fix_parmec_rigid.h"
#include "command_args.h"
#include "rank_error.h"
#include "definition_file.h"
#include "state/table_registry.h"
#include "math/inertia.h"
#include "math/quaternion.h"

#include "style_registry.h"

#include "atom.h"
#include "comm.h"
#include "error.h"
#include "group.h"
#include "input.h"
#include "memory.h"
#include "modify.h"
#include "update.h"
#include "variable.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <stdexcept>

using namespace LAMMPS_NS;
using namespace LAMMPS_NS::FixConst;
namespace sp = dembridge::springs;
using dembridge::rigid::Mat3;
using dembridge::rigid::Vec3;

namespace dembridge {

namespace {

using args::is_number;  // the commands' word readers, through LAMMPS's utils (command_args.h)

// Rotation matrix (body -> space) of a LAMMPS quaternion (w, x, y, z): the spring loops' matrix.
Mat3 rotation(const double *q)
{
  const math::BodyRotation r = math::BodyRotation::of(q);
  Mat3 m;
  m << r.m[0][0], r.m[0][1], r.m[0][2], r.m[1][0], r.m[1][1], r.m[1][2], r.m[2][0], r.m[2][1], r.m[2][2];
  return m;
}

Mat3 load(const double *a)
{
  Mat3 m;
  m << a[0], a[1], a[2], a[3], a[4], a[5], a[6], a[7], a[8];
  return m;
}

void store(const Mat3 &m, double *a)
{
  for (int r = 0; r < 3; r++)
    for (int c = 0; c < 3; c++) a[3 * r + c] = m(r, c);
}

void store_quat(const Mat3 &L, double *q)
{
  Eigen::Quaterniond e(L);
  e.normalize();
  q[0] = e.w();
  q[1] = e.x();
  q[2] = e.y();
  q[3] = e.z();
}

Vec3 vec(const double *a) { return Vec3(a[0], a[1], a[2]); }

// Global damping (spec §10) in Parmec's operation order: f − (m d_v) v and t − Λ(J(Λᵀ(d_ω ω))).
Vec3 damped_force(const Vec3 &F, double m, const double *d, const Vec3 &v)
{
  return Vec3(F[0] - m * d[0] * v[0], F[1] - m * d[1] * v[1], F[2] - m * d[2] * v[2]);
}

Vec3 damped_torque(const Vec3 &T, const Mat3 &L, const Mat3 &J, const double *d, const Vec3 &w)
{
  const Vec3 o(d[0] * w[0], d[1] * w[1], d[2] * w[2]);
  const Vec3 body = L.transpose() * o;
  const Vec3 Jb = J * body;
  return T - L * Jb;
}

void put(const Vec3 &v, double *a)
{
  a[0] = v[0];
  a[1] = v[1];
  a[2] = v[2];
}

}  // namespace

FixParmecRigid::FixParmecRigid(LAMMPS *lmp, int narg, char **arg) :
    PerAtomStateFix(lmp, narg, arg, kRecord), inertia_(lmp, cmd_)
{
  time_integrate = 1;
  peratom_flag = 1;  // Λ per atom, row-major: f_ID[1] ... f_ID[9]
  size_peratom_cols = 9;
  peratom_freq = 1;
  comm_forward = 9;  // Λ to ghost atoms (share_rotations)
  grow_arrays(atom->nmax);
  if (!atom->rmass_flag || !atom->quat_flag || !atom->omega_flag || !atom->torque_flag)
    error->all(FLERR, cmd_ + ": needs per-atom mass, quaternion, angular velocity and torque: use atom_style bpm/sphere");
  parse(std::vector<std::string>(arg + 3, arg + narg), "command line");
  if (!joint_in_.empty()) {
    array_flag = 1;
    size_array_rows = int(joint_in_.size());
    size_array_cols = 4;
    extarray = 0;
    reactions_.assign(joint_in_.size(), Vec3::Zero());
    for (const auto &j : joint_in_)
      for (tagint t : {j.tag1, j.tag2})
        if (t > 0) body_index_[t] = 0;
    for (auto &b : body_index_) {
      b.second = int(body_tags_.size());
      body_tags_.push_back(b.first);
    }
    std::vector<rigid::JointDef> defs;
    for (const auto &j : joint_in_) {
      rigid::JointDef d;
      d.body1 = body_index_[j.tag1];
      d.body2 = j.tag2 > 0 ? body_index_[j.tag2] : -1;
      defs.push_back(d);
    }
    clusters_ = std::make_unique<rigid::JointClusters>(int(body_tags_.size()), defs);
    if (!joint_file_.empty() && comm->me == 0) {
      joint_fp_ = fopen(joint_file_.c_str(), "w");
      if (!joint_fp_) fail_on_this_rank(lmp, FLERR, cmd_ + ": joint_output: cannot open '" + joint_file_ + "'");
      fprintf(joint_fp_, "STEP");
      for (const auto &j : joint_in_)
        fprintf(joint_fp_, ",j%ld_JREAC_X,j%ld_JREAC_Y,j%ld_JREAC_Z,j%ld_|JREAC|", j.id, j.id, j.id, j.id);
      fprintf(joint_fp_, "\n");
    }
  }
  resolve_all();
  define_bodies();
}

void FixParmecRigid::define_bodies()
{
  // the bodies: the group's atoms now (tags gathered from every rank, in tag order); each gets a record
  // that takes Λ and Ω from its atom at the first setup (velocities may be set after the fix)
  std::vector<long> mine, all;
  for (int i = 0; i < atom->nlocal; i++)
    if (atom->mask[i] & groupbit) mine.push_back(static_cast<long>(atom->tag[i]));
  int n = static_cast<int>(mine.size()), nprocs = comm->nprocs;
  std::vector<int> counts(nprocs), displs(nprocs, 0);
  MPI_Allgather(&n, 1, MPI_INT, counts.data(), 1, MPI_INT, world);
  for (int p = 1; p < nprocs; p++) displs[p] = displs[p - 1] + counts[p - 1];
  all.resize(std::size_t(displs.back() + counts.back()));
  MPI_Allgatherv(mine.data(), n, MPI_LONG, all.data(), counts.data(), displs.data(), MPI_LONG, world);
  std::sort(all.begin(), all.end());
  if (all.empty()) error->all(FLERR, cmd_ + ": the group has no atoms (define the fix after the atoms)");
  std::vector<std::pair<long, long>> atoms;
  for (long t : all) atoms.emplace_back(t, -1);
  define_entities("body", all, atoms, 0);
  initial_records([](int key, double *rec) {
    rec[0] = key;
    rec[1] = 1.0;  // fresh
    for (int k = 2; k < kRecord; k++) rec[k] = 0.0;
  });
}

double *FixParmecRigid::body_record(int i)
{
  return records_.count(i) ? records_.record(i, 0) : nullptr;
}

void FixParmecRigid::grow_arrays(int nmax)
{
  PerAtomStateFix::grow_arrays(nmax);
  memory->grow(rot_out_, nmax, 9, "parmec/rigid:rotation");
  array_atom = rot_out_;
}

void FixParmecRigid::fill_rotation_output()
{
  for (int i = 0; i < atom->nlocal; i++) {
    const double *L = body_record(i) ? lam(i) : nullptr;
    for (int k = 0; k < 9; k++) rot_out_[i][k] = L ? L[k] : (k % 4 == 0 ? 1.0 : 0.0);
  }
}

void FixParmecRigid::setup(int)
{
  fill_rotation_output();
}

// Λ of the local atoms from their records (after exchange or sorting the per-atom array is stale), then
// to the ghosts.
void FixParmecRigid::share_rotations()
{
  fill_rotation_output();
  comm->forward_comm(this);
}

void FixParmecRigid::setup_pre_force(int)
{
  share_rotations();  // the spring fixes' setup evaluation reads Λ (no gravity: setup applies no step)
}

void FixParmecRigid::pre_force(int)
{
  share_rotations();
  add_gravity();
}

// Parmec's forces(): the force of a particle is m g (plus contacts) before the springs add theirs
// (forces.ispc), so m g enters here, after LAMMPS cleared the forces and before the post_force fixes.
void FixParmecRigid::add_gravity()
{
  if (!has_gravity_) return;
  const double tn = step_time();
  const double g[3] = {eval(gravity_[0], tn), eval(gravity_[1], tn), eval(gravity_[2], tn)};
  double **f = atom->f;
  const double *rmass = atom->rmass;
  for (int i = 0; i < atom->nlocal; i++)
    if (atom->mask[i] & groupbit)
      for (int c = 0; c < 3; c++) f[i][c] += rmass[i] * g[c];
}

int FixParmecRigid::pack_forward_comm(int n, int *list, double *buf, int, int *)
{
  int m = 0;
  for (int k = 0; k < n; k++)
    for (int c = 0; c < 9; c++) buf[m++] = rot_out_[list[k]][c];
  return m;
}

void FixParmecRigid::unpack_forward_comm(int n, int first, double *buf)
{
  int m = 0;
  for (int i = first; i < first + n; i++)
    for (int c = 0; c < 9; c++) rot_out_[i][c] = buf[m++];
}

void FixParmecRigid::resolve_all()
{
  for (auto &g : gravity_) resolve(g, "gravity");
  for (auto &d : damp_lin_) resolve(d, "damping linear");
  for (auto &d : damp_ang_) resolve(d, "damping angular");
  for (auto &p : prescriptions_)
    for (int c = 0; c < 3; c++) {
      resolve(p.second.l[c], "prescribe " + std::to_string(p.first) + " linear");
      resolve(p.second.a[c], "prescribe " + std::to_string(p.first) + " angular");
    }
}

int FixParmecRigid::modify_param(int narg, char **arg)
{
  // between runs (Parmec: commands between DEM calls): new or replaced tseries, gravity, damping and
  // prescriptions; joints, restraints and the inertia stay as defined
  std::vector<std::string> tok(arg, arg + narg);
  const std::string &kw = tok[0];
  if (kw != "tseries" && kw != "gravity" && kw != "damping" && kw != "prescribe" && kw != "file") return 0;
  for (const auto &t : tok)
    if (t == "joint" || t == "restrain" || t == "inertia" || t == "start")
      error->all(FLERR, cmd_ + ": fix_modify: '" + t + "' cannot change after the fix is defined");
  redefine_ = true;
  parse(tok, "fix_modify");
  redefine_ = false;
  resolve_all();
  return narg;
}

FixParmecRigid::~FixParmecRigid()
{
  if (joint_fp_) fclose(joint_fp_);
  memory->destroy(rot_out_);
}

int FixParmecRigid::setmask()
{
  // PRE_FORCE: Λ to the ghosts and gravity into the force before the force fixes add theirs (Parmec's
  // order); no POST_FORCE: an integrator, its records are state only
  return FINAL_INTEGRATE | PRE_EXCHANGE | PRE_FORCE;
}

void FixParmecRigid::parse(const std::vector<std::string> &tok, const std::string &where)
{
  std::size_t i = 0;
  const std::string at = cmd_ + " (" + where + "): ";
  auto need = [&](std::size_t n, const std::string &what) {
    if (i + n >= tok.size()) error->all(FLERR, at + "'" + tok[i] + "' needs " + what + ", the arguments ended");
  };
  auto yesno = [&](const std::string &kw, const std::string &v) {
    if (v == "yes") return true;
    if (v == "no") return false;
    error->all(FLERR, at + kw + ": expected 'yes' or 'no', got '" + v + "'");
    return false;
  };
  auto tag_of = [&](const std::string &w, const std::string &kw) {
    double v;
    if (!args::parse_double(lmp, w, v) || v < 1 || v != std::floor(v))
      error->all(FLERR, at + kw + ": expected an atom ID (integer >= 1), got '" + w + "'");
    return static_cast<tagint>(v);
  };
  while (i < tok.size()) {
    const std::string kw = tok[i];
    if (kw == "tseries") {
      need(1, "an ID and values");
      const std::string sid = tok[i + 1];
      if (is_number(sid)) error->all(FLERR, at + "tseries ID '" + sid + "' must not be a number");
      if (tseries_.count(sid) && !redefine_) error->all(FLERR, at + "tseries " + sid + ": ID defined twice");
      std::vector<double> tv;
      i += 2;
      double v;
      while (i < tok.size() && args::parse_double(lmp, tok[i], v)) {
        tv.push_back(v);
        i++;
      }
      try {
        // assignment in place keeps the addresses the Series hold (std::map nodes do not move)
        if (tv.size() == 1)
          tseries_[sid] = sp::TimeSeries::constant(tv[0]);
        else
          tseries_[sid] = sp::TimeSeries::from_pairs(tv);
      } catch (std::invalid_argument &e) {
        error->all(FLERR, at + "tseries " + sid + ": " + e.what() +
                              " (expected one value, or t1 v1 t2 v2 ... with t strictly increasing)");
      }
    } else if (kw == "gravity") {
      need(3, "three values (number, tseries ID or v_name)");
      for (int c = 0; c < 3; c++) gravity_[c] = parse_series(tok[i + 1 + c], "gravity", where);
      has_gravity_ = true;
      i += 4;
    } else if (kw == "damping") {
      need(7, "'linear' and three values, 'angular' and three values");
      if (tok[i + 1] != "linear" || tok[i + 5] != "angular")
        error->all(FLERR, at + "damping: expected 'damping linear D D D angular D D D'");
      for (int c = 0; c < 3; c++) {
        damp_lin_[c] = parse_series(tok[i + 2 + c], "damping linear", where);
        damp_ang_[c] = parse_series(tok[i + 6 + c], "damping angular", where);
      }
      has_damping_ = true;
      i += 9;
    } else if (kw == "restrain") {
      need(1, "an atom ID");
      const tagint tag = tag_of(tok[i + 1], "restrain");
      if (restraints_.count(tag)) error->all(FLERR, at + "restrain: atom " + tok[i + 1] + " restrained twice");
      Restraint r;
      i += 2;
      while (i < tok.size() && (tok[i] == "linear" || tok[i] == "angular")) {
        const bool lin = tok[i] == "linear";
        std::vector<double> d;
        i++;
        double v;
        while (i < tok.size() && args::parse_double(lmp, tok[i], v)) {
          d.push_back(v);
          i++;
        }
        if (d.size() != 3 && d.size() != 6 && d.size() != 9)
          error->all(FLERR, at + "restrain " + std::to_string(tag) + (lin ? " linear" : " angular") +
                                ": expected 3, 6 or 9 numbers (up to three directions), got " + std::to_string(d.size()));
        if (lin)
          r.nlin = rigid::orthonormalise(d.data(), int(d.size() / 3), r.lin);
        else
          r.nang = rigid::orthonormalise(d.data(), int(d.size() / 3), r.ang);
      }
      restraints_[tag] = r;
    } else if (kw == "prescribe") {
      need(1, "an atom ID");
      const tagint tag = tag_of(tok[i + 1], "prescribe");
      if (prescriptions_.count(tag) && !redefine_)
        error->all(FLERR, at + "prescribe: atom " + tok[i + 1] + " prescribed twice");
      Prescription p;
      i += 2;
      while (i < tok.size() && (tok[i] == "linear" || tok[i] == "angular")) {
        const bool lin = tok[i] == "linear";
        const std::string what = "prescribe " + std::to_string(tag) + (lin ? " linear" : " angular");
        if (i + 4 >= tok.size()) error->all(FLERR, at + what + ": expected 'v' or 'a' and three values");
        const std::string kind = tok[i + 1];
        if (kind != "v" && kind != "a")
          error->all(FLERR, at + what + ": expected kind 'v' (velocity) or 'a' (acceleration), got '" + kind + "'");
        for (int c = 0; c < 3; c++) (lin ? p.l[c] : p.a[c]) = parse_series(tok[i + 2 + c], what, where);
        (lin ? p.lin : p.ang) = true;
        (lin ? p.lin_acc : p.ang_acc) = kind == "a";
        i += 5;
      }
      if (!p.lin && !p.ang) error->all(FLERR, at + "prescribe " + std::to_string(tag) + ": expected 'linear' and/or 'angular'");
      prescriptions_[tag] = p;
    } else if (kw == "joint") {
      need(6, "an ID, atom ID 1, the point x y z and atom ID 2 (or -1)");
      JointInput j;
      double v;
      if (!args::parse_double(lmp, tok[i + 1], v) || v != std::floor(v))
        error->all(FLERR, at + "joint: expected an integer joint ID, got '" + tok[i + 1] + "'");
      j.id = static_cast<long>(v);
      for (const auto &o : joint_in_)
        if (o.id == j.id) error->all(FLERR, at + "joint " + tok[i + 1] + ": ID defined twice");
      j.tag1 = tag_of(tok[i + 2], "joint " + tok[i + 1] + " atom 1");
      for (int c = 0; c < 3; c++)
        if (!args::parse_double(lmp, tok[i + 3 + c], j.point[c]))
          error->all(FLERR, at + "joint " + tok[i + 1] + ": expected the point x y z, got '" + tok[i + 3 + c] + "'");
      if (tok[i + 6] == "-1")
        j.tag2 = -1;
      else
        j.tag2 = tag_of(tok[i + 6], "joint " + tok[i + 1] + " atom 2 (or -1)");
      if (j.tag1 == j.tag2) error->all(FLERR, at + "joint " + tok[i + 1] + ": joins atom " + tok[i + 2] + " with itself");
      joint_in_.push_back(j);
      i += 7;
    } else if (kw == "joint_output") {
      need(1, "a file name");
      joint_file_ = tok[i + 1];
      i += 2;
    } else if (kw == "inertia") {
      need(1, "'sphere' or the name of a d2_ property with 6 columns");
      inertia_.set_name(tok[i + 1] == "sphere" ? "" : tok[i + 1]);
      i += 2;
    } else if (kw == "start") {
      need(1, "'parmec' or 'none'");
      if (tok[i + 1] != "parmec" && tok[i + 1] != "none")
        error->all(FLERR, at + "start: expected 'parmec' (initial half drift) or 'none', got '" + tok[i + 1] + "'");
      half_drift_ = tok[i + 1] == "parmec";
      i += 2;
    } else if (kw == "taylor") {
      need(1, "'parmec' or 'exact'");
      if (tok[i + 1] != "parmec" && tok[i + 1] != "exact")
        error->all(FLERR, at + "taylor: expected 'parmec' (single-precision series coefficients, Q26) or 'exact', got '" +
                              tok[i + 1] + "'");
      q26_ = tok[i + 1] == "parmec";
      i += 2;
    } else if (kw == "q1" || kw == "q2" || kw == "q3" || kw == "q20" || kw == "qj" || kw == "q16") {
      need(1, "'yes' or 'no'");
      const bool on = yesno(kw, tok[i + 1]);
      (kw == "q1" ? q1_ : kw == "q2" ? q2_ : kw == "q3" ? q3_ : kw == "q20" ? q20_ : kw == "q16" ? q16_ : qj_) = on;
      i += 2;
    } else if (kw == "quirks") {
      need(1, "'parmec' or 'none'");
      if (tok[i + 1] != "parmec" && tok[i + 1] != "none")
        error->all(FLERR, at + "quirks: expected 'parmec' or 'none', got '" + tok[i + 1] + "'");
      q1_ = q2_ = q3_ = q20_ = qj_ = q16_ = q26_ = tok[i + 1] == "parmec";
      i += 2;
    } else if (kw == "file") {
      need(1, "a file name");
      const std::string path = tok[i + 1];
      parse_definition_file(lmp, path, cmd_,
                            [this](const std::vector<std::string> &words, const std::string &w) { parse(words, w); });
      i += 2;
    } else {
      error->all(FLERR, at + "unknown keyword '" + kw +
                            "' (expected tseries, gravity, damping, restrain, prescribe, joint, joint_output, inertia, "
                            "start, taylor, quirks, q1, q2, q3, q16, q20, qj or file)");
    }
  }
}

FixParmecRigid::Series FixParmecRigid::parse_series(const std::string &word, const std::string &what,
                                                    const std::string &where)
{
  Series s;
  if (args::parse_double(lmp, word, s.value)) return s;
  if (word.rfind("v_", 0) == 0) {
    s.kind = 2;
    s.name = word.substr(2);
    if (s.name.empty()) error->all(FLERR, cmd_ + " (" + where + "): " + what + ": empty variable name in '" + word + "'");
    return s;
  }
  s.kind = 1;
  s.name = word;
  return s;
}

void FixParmecRigid::resolve(Series &s, const std::string &what)
{
  if (s.kind == 1) {
    auto it = tseries_.find(s.name);
    if (it == tseries_.end())
      error->all(FLERR, cmd_ + ": " + what + ": '" + s.name +
                            "' is neither a number, a v_name variable nor the ID of a 'tseries' definition");
    s.ts = &it->second;
  }
}

double FixParmecRigid::eval(const Series &s, double t)
{
  if (s.kind == 0) return s.value;
  if (s.kind == 1) return s.ts->value_clamped(t);
  return input->variable->compute_equal(s.ivar);
}

void FixParmecRigid::init()
{
  auto check_var = [&](Series &s, const std::string &what) {
    if (s.kind != 2) return;
    s.ivar = input->variable->find(s.name.c_str());
    if (s.ivar < 0) error->all(FLERR, cmd_ + ": " + what + ": variable '" + s.name + "' does not exist");
    if (!input->variable->equalstyle(s.ivar))
      error->all(FLERR, cmd_ + ": " + what + ": variable '" + s.name + "' is not equal-style");
  };
  for (auto &g : gravity_) check_var(g, "gravity");
  for (auto &d : damp_lin_) check_var(d, "damping linear");
  for (auto &d : damp_ang_) check_var(d, "damping angular");
  for (auto &p : prescriptions_)
    for (int c = 0; c < 3; c++) {
      check_var(p.second.l[c], "prescribe");
      check_var(p.second.a[c], "prescribe");
    }
  // every restrained / prescribed atom must exist (exactly once) and be in the group
  auto check_tags = [&](const char *what, auto &defs) {
    for (auto &d : defs) {
      int here = 0, total = 0;
      for (int i = 0; i < atom->nlocal; i++)
        if (atom->tag[i] == d.first) here += (atom->mask[i] & groupbit) ? 1 : 1000;
      MPI_Allreduce(&here, &total, 1, MPI_INT, MPI_SUM, world);
      if (total == 0) error->all(FLERR, cmd_ + ": " + what + " " + std::to_string(d.first) + ": no atom with this ID");
      if (total >= 1000)
        error->all(FLERR, cmd_ + ": " + what + " " + std::to_string(d.first) + ": the atom is not in the fix group");
    }
  };
  check_tags("restrain", restraints_);
  check_tags("prescribe", prescriptions_);
  std::map<tagint, int> jointed;
  for (tagint t : body_tags_) jointed[t] = 0;
  check_tags("joint atom", jointed);
  for (const auto &j : joint_in_)
    for (tagint t : {j.tag1, j.tag2}) {
      auto p = prescriptions_.find(t);
      if (t <= 0 || p == prescriptions_.end()) continue;
      const Prescription &q = p->second;
      if (!(q.lin && q.ang && !q.lin_acc && !q.ang_acc))
        error->all(FLERR, cmd_ + ": joint " + std::to_string(j.id) + ": atom " + std::to_string(t) +
                              " is prescribed partly or by acceleration; a jointed body may only be prescribed by "
                              "velocity, linear and angular (it then drives the joint)");
      if (j.tag2 == -1)
        error->all(FLERR, cmd_ + ": joint " + std::to_string(j.id) + ": atom " + std::to_string(t) +
                              " is both pinned in space by the joint and prescribed (its motion is given twice)");
    }
  find_inertia();
  check_inertia();
  // every atom of the group is a body with a record (the group's atoms when the fix was defined)
  check_record_count();
  int missing = 0, any = 0;
  for (int i = 0; i < atom->nlocal; i++)
    if ((atom->mask[i] & groupbit) && !body_record(i)) missing = 1;
  MPI_Allreduce(&missing, &any, 1, MPI_INT, MPI_MAX, world);
  if (any)
    error->all(FLERR, cmd_ + ": an atom of the group has no rigid-body state: it was created after the fix "
                             "(define fix parmec/rigid after the atoms)");
}

Mat3 FixParmecRigid::inertia(int i) const
{
  return rigid::to_mat3(J_ ? math::inertia_from_list(J_[i]) : math::sphere_inertia(atom->rmass[i], atom->radius[i]));
}

void FixParmecRigid::setup_joints()
{
  // arms from the reference configuration: every rank gets (tag, x, Λ) of the jointed bodies
  const int nb = int(body_tags_.size());
  std::vector<double> mine, all(std::size_t(nb) * 13, 0.0);
  for (int i = 0; i < atom->nlocal; i++) {
    auto it = body_index_.find(atom->tag[i]);
    if (it == body_index_.end()) continue;
    double *rec = &all[std::size_t(it->second) * 13];
    rec[0] = 1.0;
    for (int c = 0; c < 3; c++) rec[1 + c] = atom->x[i][c];
    for (int k = 0; k < 9; k++) rec[4 + k] = lam(i)[k];
  }
  std::vector<double> sum(all.size());
  MPI_Allreduce(all.data(), sum.data(), int(all.size()), MPI_DOUBLE, MPI_SUM, world);
  arms_.assign(2 * joint_in_.size(), Vec3::Zero());
  for (std::size_t j = 0; j < joint_in_.size(); j++) {
    const JointInput &in = joint_in_[j];
    for (int e = 0; e < 2; e++) {
      const tagint t = e == 0 ? in.tag1 : in.tag2;
      if (t <= 0) continue;
      const double *rec = &sum[std::size_t(body_index_[t]) * 13];
      const Vec3 P(in.point[0], in.point[1], in.point[2]), X(rec[1], rec[2], rec[3]);
      arms_[2 * j + e] = load(rec + 4).transpose() * (P - X);
    }
  }
  for (std::size_t j = 0; j < joint_in_.size(); j++)
    for (int e = 0; e < 2; e++) clusters_->set_arm(int(j), e, arms_[2 * j + e]);
}

void FixParmecRigid::apply_joints(std::vector<Vec3> &F0, std::vector<Vec3> &T0, const double *dl, const double *da,
                                  double tv)
{
  constexpr int kRec = 29;
  const double h = update->dt;
  std::vector<double> mine;
  for (int i = 0; i < atom->nlocal; i++) {
    auto it = body_index_.find(atom->tag[i]);
    if (it == body_index_.end() || !(atom->mask[i] & groupbit)) continue;
    const Mat3 J = inertia(i), L = load(lam(i));
    const Vec3 v = vec(atom->v[i]), w = vec(atom->omega[i]);
    const double m = atom->rmass[i];
    // free end-of-step motion includes global damping (spec §9)
    const Vec3 F = damped_force(F0[i], m, dl, v);
    const Vec3 T = damped_torque(T0[i], L, J, da, w);
    mine.push_back(it->second);
    mine.push_back(m);
    const double six[6] = {J(0, 0), J(1, 1), J(2, 2), J(0, 1), J(0, 2), J(1, 2)};
    mine.insert(mine.end(), six, six + 6);
    mine.insert(mine.end(), lam(i), lam(i) + 9);
    mine.insert(mine.end(), omg(i), omg(i) + 3);
    for (const Vec3 *a : {&v, &F, &T}) mine.insert(mine.end(), a->data(), a->data() + 3);
  }
  int n = int(mine.size()), nprocs = comm->nprocs;
  std::vector<int> counts(nprocs), displs(nprocs, 0);
  MPI_Allgather(&n, 1, MPI_INT, counts.data(), 1, MPI_INT, world);
  for (int p = 1; p < nprocs; p++) displs[p] = displs[p - 1] + counts[p - 1];
  std::vector<double> all(std::size_t(displs[nprocs - 1] + counts[nprocs - 1]));
  MPI_Allgatherv(mine.data(), n, MPI_DOUBLE, all.data(), counts.data(), displs.data(), MPI_DOUBLE, world);

  std::vector<rigid::BodyKinematics> bodies(body_tags_.size());
  std::vector<char> seen(body_tags_.size(), 0);
  for (std::size_t k = 0; k + kRec <= all.size(); k += kRec) {
    const double *r = &all[k];
    const int b = int(r[0]);
    seen[b] = 1;
    rigid::BodyKinematics &B = bodies[b];
    const Mat3 J = rigid::to_mat3(math::inertia_from_list(r + 2));
    B.L = load(r + 8);
    B.W = Vec3(r[17], r[18], r[19]);
    B.v = Vec3(r[20], r[21], r[22]);
    auto p = prescriptions_.find(body_tags_[b]);
    if (p != prescriptions_.end()) {
      // kinematic driver: prescribed velocities at the end of the step, infinite mass in the joint solve
      const Prescription &q = p->second;
      B.v_free = Vec3(eval(q.l[0], tv), eval(q.l[1], tv), eval(q.l[2], tv));
      B.W_free = B.L.transpose() * Vec3(eval(q.a[0], tv), eval(q.a[1], tv), eval(q.a[2], tv));
      continue;
    }
    B.inv_mass = 1.0 / r[1];
    B.inv_inertia = rigid::parmec_inverse(J);
    B.v_free = B.v;
    B.kick = (h * B.inv_mass) * Vec3(r[23], r[24], r[25]);
    B.W_free = rigid::rotation_step(J, B.inv_inertia, B.L, B.W, Vec3(r[26], r[27], r[28]), h, q3_).W;  // joints.cpp (C++): double coefficients
  }
  for (std::size_t b = 0; b < seen.size(); b++)
    if (!seen[b])
      error->all(FLERR, cmd_ + ": joint atom " + std::to_string(body_tags_[b]) + " is not in the fix group or was lost");
  rigid::JointClusters &cl = *clusters_;
  const std::vector<rigid::JointDef> &defs = cl.joints();
  try {
    reactions_ = cl.solve(bodies, h, q16_);
  } catch (rigid::SingularCluster &e) {
    std::string ids;
    for (int j : e.joints) ids += " " + std::to_string(joint_in_[j].id);
    error->all(FLERR, cmd_ + ": singular joint cluster (joints" + ids +
                          "): the joints constrain the same motion twice, e.g. a body pinned twice at one point");
  }
  for (int i = 0; i < atom->nlocal; i++) {
    auto it = body_index_.find(atom->tag[i]);
    if (it == body_index_.end() || !(atom->mask[i] & groupbit)) continue;
    const Mat3 L = load(lam(i));
    for (std::size_t j = 0; j < joint_in_.size(); j++) {
      const rigid::JointDef &d = defs[j];
      for (int e = 0; e < 2; e++) {
        if ((e == 0 ? d.body1 : d.body2) != it->second) continue;
        const Vec3 R = (e == 0 ? 1.0 : -1.0) * reactions_[j];
        F0[i] += R;
        T0[i] += rigid::macro_mv(L, arms_[2 * j + e]).cross(R);  // joints.cpp: NVMUL, then R × a
      }
    }
  }
  if (joint_fp_) {
    fprintf(joint_fp_, BIGINT_FORMAT, update->ntimestep);
    for (const Vec3 &R : reactions_) fprintf(joint_fp_, ",%.17g,%.17g,%.17g,%.17g", R[0], R[1], R[2], R.norm());
    fprintf(joint_fp_, "\n");
    fflush(joint_fp_);
  }
}

double FixParmecRigid::compute_array(int i, int j)
{
  if (i < 0 || i >= int(reactions_.size())) return 0.0;
  return j < 3 ? reactions_[i][j] : reactions_[i].norm();
}

void FixParmecRigid::find_inertia()
{
  // the inertia property is looked up at each use: Atom::sort and exchange reallocate per-atom arrays
  J_ = inertia_.rows();
}

// A body must have a positive definite inertia tensor (J⁻¹ and the rotational update divide by it): an
// all-zero or singular tensor would give NaN or infinite spins without a word. Sylvester's criterion.
void FixParmecRigid::check_inertia()
{
  tagint bad = MAXTAGINT;
  for (int i = 0; i < atom->nlocal; i++) {
    if (!(atom->mask[i] & groupbit)) continue;
    if (!math::positive_definite(rigid::to_mat9(inertia(i)))) bad = std::min(bad, atom->tag[i]);
  }
  tagint first = MAXTAGINT;
  MPI_Allreduce(&bad, &first, 1, MPI_LMP_TAGINT, MPI_MIN, world);
  if (first == MAXTAGINT) return;
  double six[6] = {0, 0, 0, 0, 0, 0}, all[6];  // the owner's tensor, for the message on every rank
  const int i = atom->map(first);
  if (i >= 0 && i < atom->nlocal) {
    const Mat3 J = inertia(i);
    const double v[6] = {J(0, 0), J(1, 1), J(2, 2), J(0, 1), J(0, 2), J(1, 2)};
    std::copy(v, v + 6, six);
  }
  MPI_Allreduce(six, all, 6, MPI_DOUBLE, MPI_SUM, world);
  error->all(FLERR, fmt::format("{}: atom {}: its inertia tensor (Ixx Iyy Izz Ixy Ixz Iyz = {} {} {} {} {} {}{}) is not "
                                "positive definite: a rigid body needs three positive principal moments",
                                cmd_, first, all[0], all[1], all[2], all[3], all[4], all[5],
                                inertia_.name().empty() ? ", the sphere's 0.4 m r^2" : ", from d2_" + inertia_.name()));
}

double FixParmecRigid::step_time() const
{
  // Parmec's clock: the step times are accumulated (t_{n+1} = t_n + h), which decides on which side of a
  // TSERIES breakpoint a step falls; kept in the restart file
  return curtime_;
}

void FixParmecRigid::setup_pre_exchange()
{
  find_inertia();
  const int nlocal = atom->nlocal;
  // bodies met for the first time: Λ from the quaternion, Ω = Λᵀ ω
  for (int i = 0; i < nlocal; i++) {
    double *rec = body_record(i);
    if (!rec || rec[1] == 0.0) continue;
    const Mat3 L = rotation(atom->quat[i]);
    store(L, lam(i));
    put(L.transpose() * vec(atom->omega[i]), omg(i));
    rec[1] = 0.0;
  }
  if (!started_ && clusters_) setup_joints();
  if (!q2_) {
    // corrected: a prescribed velocity holds from the start of every run (Parmec, Q2: the first step of a
    // DEM call uses the velocity the particle has)
    for (int i = 0; i < nlocal; i++) {
      auto it = prescriptions_.find(atom->tag[i]);
      if (it == prescriptions_.end() || !(atom->mask[i] & groupbit)) continue;
      const Prescription &p = it->second;
      if (p.lin && !p.lin_acc)
        for (int c = 0; c < 3; c++) atom->v[i][c] = eval(p.l[c], curtime_);
      if (p.ang && !p.ang_acc) {
        for (int c = 0; c < 3; c++) atom->omega[i][c] = eval(p.a[c], curtime_);
        put(load(lam(i)).transpose() * vec(atom->omega[i]), omg(i));
      }
    }
  }
  if (!started_) {
    if (!q20_) restrain_velocities();
    if (half_drift_) half_drift();
    if (q20_) restrain_velocities();
    started_ = 1;
  } else {
    restrain_velocities();
  }
}

void FixParmecRigid::restrain_velocities()
{
  for (int i = 0; i < atom->nlocal; i++) {
    auto it = restraints_.find(atom->tag[i]);
    if (it == restraints_.end() || !(atom->mask[i] & groupbit)) continue;
    const Restraint &r = it->second;
    put(rigid::remove_components(vec(atom->v[i]), r.lin, r.nlin), atom->v[i]);
    put(rigid::remove_components(vec(atom->omega[i]), r.ang, r.nang), atom->omega[i]);
    const Mat3 L = load(lam(i));
    Vec3 body[3];
    for (int k = 0; k < r.nang; k++) body[k] = L.transpose() * r.ang[k];
    put(rigid::remove_components(vec(omg(i)), body, r.nang), omg(i));
  }
}

void FixParmecRigid::half_drift()
{
  // Parmec's unforced first half step: x_{1/2} = x0 + h/2 v0, Λ_{1/2} = Λ0 exp(h/2 Ω0); the spatial ω of the
  // first force evaluation is Λ_{1/2} Ω0 (Q1: Λ_{1/2} (h/2) Ω0)
  const double hh = 0.5 * update->dt;
  find_inertia();
  for (int i = 0; i < atom->nlocal; i++) {
    if (!(atom->mask[i] & groupbit)) continue;
    for (int c = 0; c < 3; c++) atom->x[i][c] += hh * atom->v[i][c];
    const Vec3 W = vec(omg(i));
    const Mat3 L = load(lam(i)) * rigid::expmap(hh * W, q3_, q26_);
    store(L, lam(i));
    store_quat(L, atom->quat[i]);
    put(L * (q1_ ? Vec3(hh * W) : W), atom->omega[i]);
  }
}

void FixParmecRigid::final_integrate()
{
  find_inertia();  // the per-atom arrays move when atoms are sorted or exchanged (Atom::sort grows them)
  const double h = update->dt;
  const double tn = step_time();
  double dl[3] = {0, 0, 0}, da[3] = {0, 0, 0};
  for (int c = 0; c < 3; c++) {
    if (has_damping_) {
      dl[c] = eval(damp_lin_[c], tn);
      da[c] = eval(damp_ang_[c], tn);
    }
  }
  const double tv = q2_ ? tn : tn + h;  // time of a prescribed velocity (Q2: one step late)
  double **x = atom->x, **v = atom->v, **f = atom->f, **omega = atom->omega, **torque = atom->torque;
  const double *rmass = atom->rmass;
  const int *mask = atom->mask;
  const int nlocal = atom->nlocal;
  // forces of the step: gravity (pre_force) and the other fixes' forces, then the joint reactions (spec
  // §1.1 steps 3-6)
  std::vector<Vec3> F0(nlocal), T0(nlocal);
  for (int i = 0; i < nlocal; i++) {
    F0[i] = vec(f[i]);
    T0[i] = vec(torque[i]);
  }
  if (clusters_) apply_joints(F0, T0, dl, da, tv);
  for (int i = 0; i < nlocal; i++) {
    if (!(mask[i] & groupbit)) continue;
    const double m = rmass[i];
    const Mat3 J = inertia(i);
    const Mat3 Jinv = rigid::parmec_inverse(J);
    const Mat3 L = load(lam(i));
    Vec3 F = F0[i];
    Vec3 T = T0[i];
    const Vec3 vn = vec(v[i]), wn = vec(omega[i]);

    auto r = restraints_.find(atom->tag[i]);
    if (r != restraints_.end()) {
      F = rigid::remove_components(F, r->second.lin, r->second.nlin);
      T = rigid::remove_components(T, r->second.ang, r->second.nang);
    }
    auto pit = prescriptions_.find(atom->tag[i]);
    const Prescription *p = pit == prescriptions_.end() ? nullptr : &pit->second;
    if (p && p->lin) {
      if (p->lin_acc)
        F = m * Vec3(eval(p->l[0], tn), eval(p->l[1], tn), eval(p->l[2], tn));
      else
        F.setZero();
    }
    if (p && p->ang) {
      if (p->ang_acc) {
        const Vec3 alpha(eval(p->a[0], tn), eval(p->a[1], tn), eval(p->a[2], tn));
        T = qj_ ? Vec3(J * alpha) : Vec3(L * J * L.transpose() * alpha);  // qj: Parmec's referential J
      } else {
        T.setZero();
      }
    }
    if (has_damping_) {
      F = damped_force(F, m, dl, vn);
      T = damped_torque(T, L, J, da, wn);
    }
    put(F, f[i]);
    put(T, torque[i]);

    // Parmec: 1/m stored, times h, times f; 'taylor parmec' (its ISPC build, Q27) fuses the multiply-adds
    // v + c f and x + h v (one rounding each)
    const double ch = (1.0 / m) * h;
    const Vec3 v1 = q26_ ? Vec3(std::fma(ch, F[0], vn[0]), std::fma(ch, F[1], vn[1]), std::fma(ch, F[2], vn[2]))
                         : Vec3(vn + ch * F);
    const rigid::RotationStep rot = rigid::rotation_step(J, Jinv, L, vec(omg(i)), T, h, q3_, q26_);
    for (int c = 0; c < 3; c++) x[i][c] = q26_ ? std::fma(h, v1[c], x[i][c]) : x[i][c] + h * v1[c];
    put(v1, v[i]);
    Vec3 W = rot.W, w = rot.w;
    if (p && p->lin && !p->lin_acc)
      for (int c = 0; c < 3; c++) v[i][c] = eval(p->l[c], tv);
    if (p && p->ang && !p->ang_acc) {
      w = Vec3(eval(p->a[0], tv), eval(p->a[1], tv), eval(p->a[2], tv));
      W = rot.L.transpose() * w;
    }
    store(rot.L, lam(i));
    put(W, omg(i));
    put(w, omega[i]);
    store_quat(rot.L, atom->quat[i]);
  }
  curtime_ += h;
  fill_rotation_output();
}

void FixParmecRigid::write_restart(FILE *fp)
{
  if (comm->me == 0) {
    std::vector<double> data = {double(started_), double(arms_.size()), curtime_};
    for (const Vec3 &a : arms_) data.insert(data.end(), a.data(), a.data() + 3);
    const int n = int(data.size() * sizeof(double));
    fwrite(&n, sizeof(int), 1, fp);
    fwrite(data.data(), sizeof(double), data.size(), fp);
  }
}

void FixParmecRigid::restart(char *buf)
{
  const double *d = reinterpret_cast<double *>(buf);
  started_ = d[0] != 0.0;
  const std::size_t na = std::size_t(d[1]);
  if (na != arms_.size() && na != 2 * joint_in_.size())
    error->all(FLERR, cmd_ + ": the restart file holds " + std::to_string(na / 2) + " joints, this fix defines " +
                          std::to_string(joint_in_.size()) + " (re-issue the same fix command)");
  arms_.assign(na, Vec3::Zero());
  curtime_ = d[2];
  for (std::size_t k = 0; k < na; k++) arms_[k] = Vec3(d[3 + 3 * k], d[4 + 3 * k], d[5 + 3 * k]);
  if (clusters_)
    for (std::size_t j = 0; j < joint_in_.size(); j++)
      for (int e = 0; e < 2; e++) clusters_->set_arm(int(j), e, arms_[2 * j + e]);
}

static void *create_fix_parmec_rigid(void *lmp, int narg, char **arg)
{
  return new FixParmecRigid(static_cast<LAMMPS *>(lmp), narg, arg);
}
static RegisterStyle reg_fix_parmec_rigid("fix", "parmec/rigid",
                                          "Parmec rigid-body integrator with RESTRAIN, PRESCRIBE, DAMPING, GRAVITY",
                                          create_fix_parmec_rigid);

}  // namespace dembridge
