// fix parmec/rigid: see fix_parmec_rigid.h and doc/fix_parmec_rigid.md.
#include "fix_parmec_rigid.h"
#include "definition_file.h"

#include "style_registry.h"

#include "atom.h"
#include "comm.h"
#include "error.h"
#include "group.h"
#include "input.h"
#include "modify.h"
#include "update.h"
#include "variable.h"

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

bool parse_double(const std::string &s, double &v)
{
  if (s.empty()) return false;
  char *end = nullptr;
  v = std::strtod(s.c_str(), &end);
  return end && *end == '\0';
}

bool is_number(const std::string &s)
{
  double v;
  return parse_double(s, v);
}

// Row-major rotation matrix (body -> space) of a LAMMPS quaternion (w, x, y, z).
Mat3 rotation(const double *q)
{
  const double w = q[0], x = q[1], y = q[2], z = q[3];
  Mat3 m;
  m << w * w + x * x - y * y - z * z, 2.0 * (x * y - w * z), 2.0 * (x * z + w * y),  //
      2.0 * (x * y + w * z), w * w - x * x + y * y - z * z, 2.0 * (y * z - w * x),    //
      2.0 * (x * z - w * y), 2.0 * (y * z + w * x), w * w - x * x - y * y + z * z;
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

void put(const Vec3 &v, double *a)
{
  a[0] = v[0];
  a[1] = v[1];
  a[2] = v[2];
}

}  // namespace

FixParmecRigid::FixParmecRigid(LAMMPS *lmp, int narg, char **arg) : Fix(lmp, narg, arg)
{
  cmd_ = std::string("fix ") + arg[0] + " parmec/rigid";
  time_integrate = 1;
  restart_global = 1;
  if (!atom->rmass_flag || !atom->quat_flag || !atom->omega_flag || !atom->torque_flag)
    error->all(FLERR, cmd_ + ": needs per-atom mass, quaternion, angular velocity and torque: use atom_style bpm/sphere");
  parse(std::vector<std::string>(arg + 3, arg + narg), "command line");
  for (auto &g : gravity_) resolve(g, "gravity");
  for (auto &d : damp_lin_) resolve(d, "damping linear");
  for (auto &d : damp_ang_) resolve(d, "damping angular");
  for (auto &p : prescriptions_)
    for (int c = 0; c < 3; c++) {
      resolve(p.second.l[c], "prescribe " + std::to_string(p.first) + " linear");
      resolve(p.second.a[c], "prescribe " + std::to_string(p.first) + " angular");
    }
}

FixParmecRigid::~FixParmecRigid()
{
  if (!id_state_.empty() && modify && modify->nfix && modify->get_fix_by_id(id_state_)) modify->delete_fix(id_state_);
}

void FixParmecRigid::post_constructor()
{
  id_state_ = std::string(id) + "_STATE";
  modify->add_fix(id_state_ + " " + group->names[igroup] + " property/atom d2_" + id + "_L 9 d2_" + id + "_W 3 ghost no");
}

int FixParmecRigid::setmask()
{
  return FINAL_INTEGRATE | PRE_EXCHANGE;
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
    if (!parse_double(w, v) || v < 1 || v != std::floor(v))
      error->all(FLERR, at + kw + ": expected an atom ID (integer >= 1), got '" + w + "'");
    return static_cast<tagint>(v);
  };
  while (i < tok.size()) {
    const std::string kw = tok[i];
    if (kw == "tseries") {
      need(1, "an ID and values");
      const std::string sid = tok[i + 1];
      if (is_number(sid)) error->all(FLERR, at + "tseries ID '" + sid + "' must not be a number");
      if (tseries_.count(sid)) error->all(FLERR, at + "tseries " + sid + ": ID defined twice");
      std::vector<double> tv;
      i += 2;
      double v;
      while (i < tok.size() && parse_double(tok[i], v)) {
        tv.push_back(v);
        i++;
      }
      try {
        if (tv.size() == 1)
          tseries_.emplace(sid, sp::TimeSeries::constant(tv[0]));
        else
          tseries_.emplace(sid, sp::TimeSeries::from_pairs(tv));
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
        while (i < tok.size() && parse_double(tok[i], v)) {
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
      if (prescriptions_.count(tag)) error->all(FLERR, at + "prescribe: atom " + tok[i + 1] + " prescribed twice");
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
    } else if (kw == "inertia") {
      need(1, "'sphere' or the name of a d2_ property with 6 columns");
      inertia_name_ = tok[i + 1] == "sphere" ? "" : tok[i + 1];
      i += 2;
    } else if (kw == "start") {
      need(1, "'parmec' or 'none'");
      if (tok[i + 1] != "parmec" && tok[i + 1] != "none")
        error->all(FLERR, at + "start: expected 'parmec' (initial half drift) or 'none', got '" + tok[i + 1] + "'");
      half_drift_ = tok[i + 1] == "parmec";
      i += 2;
    } else if (kw == "q1" || kw == "q2" || kw == "q3" || kw == "q20" || kw == "qj") {
      need(1, "'yes' or 'no'");
      const bool on = yesno(kw, tok[i + 1]);
      (kw == "q1" ? q1_ : kw == "q2" ? q2_ : kw == "q3" ? q3_ : kw == "q20" ? q20_ : qj_) = on;
      i += 2;
    } else if (kw == "quirks") {
      need(1, "'parmec' or 'none'");
      if (tok[i + 1] != "parmec" && tok[i + 1] != "none")
        error->all(FLERR, at + "quirks: expected 'parmec' or 'none', got '" + tok[i + 1] + "'");
      q1_ = q2_ = q3_ = q20_ = qj_ = tok[i + 1] == "parmec";
      i += 2;
    } else if (kw == "file") {
      need(1, "a file name");
      const std::string path = tok[i + 1];
      parse(read_definition_words(lmp, path, cmd_), "file " + path);
      i += 2;
    } else {
      error->all(FLERR, at + "unknown keyword '" + kw +
                            "' (expected tseries, gravity, damping, restrain, prescribe, inertia, start, quirks, "
                            "q1, q2, q3, q20, qj or file)");
    }
  }
}

FixParmecRigid::Series FixParmecRigid::parse_series(const std::string &word, const std::string &what,
                                                    const std::string &where)
{
  Series s;
  if (parse_double(word, s.value)) return s;
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
  refresh_state();
}

void FixParmecRigid::refresh_state()
{
  int flag = 0, cols = 0;
  const int il = atom->find_custom((std::string(id) + "_L").c_str(), flag, cols);
  const int iw = atom->find_custom((std::string(id) + "_W").c_str(), flag, cols);
  if (il < 0 || iw < 0) error->all(FLERR, cmd_ + ": internal per-atom state (fix " + id_state_ + ") is missing");
  L_ = atom->darray[il];
  W_ = atom->darray[iw];
  J_ = nullptr;
  if (!inertia_name_.empty()) {
    const int ij = atom->find_custom(inertia_name_.c_str(), flag, cols);
    if (ij < 0 || flag != 1 || cols != 6)
      error->all(FLERR, cmd_ + ": inertia: '" + inertia_name_ +
                            "' is not a per-atom d2_ property with 6 columns (define it with fix property/atom d2_" +
                            inertia_name_ + " 6 and set Ixx Iyy Izz Ixy Ixz Iyz)");
    J_ = atom->darray[ij];
  }
}

double FixParmecRigid::step_time() const
{
  return update->atime + double(update->ntimestep - 1 - update->atimestep) * update->dt;
}

void FixParmecRigid::setup_pre_exchange()
{
  refresh_state();
  const int nlocal = atom->nlocal;
  // atoms met for the first time: Λ from the quaternion, Ω = Λᵀ ω
  for (int i = 0; i < nlocal; i++) {
    if (!(atom->mask[i] & groupbit)) continue;
    bool fresh = true;
    for (int k = 0; k < 9; k++) fresh = fresh && L_[i][k] == 0.0;
    if (!fresh) continue;
    const Mat3 L = rotation(atom->quat[i]);
    store(L, L_[i]);
    put(L.transpose() * vec(atom->omega[i]), W_[i]);
  }
  if (!started_) {
    if (!q2_) {
      // corrected start: a prescribed velocity holds from t = 0 (Parmec, Q2: the initial velocity is used)
      const double t0 = update->atime + double(update->ntimestep - update->atimestep) * update->dt;
      for (int i = 0; i < nlocal; i++) {
        auto it = prescriptions_.find(atom->tag[i]);
        if (it == prescriptions_.end() || !(atom->mask[i] & groupbit)) continue;
        const Prescription &p = it->second;
        if (p.lin && !p.lin_acc)
          for (int c = 0; c < 3; c++) atom->v[i][c] = eval(p.l[c], t0);
        if (p.ang && !p.ang_acc) {
          for (int c = 0; c < 3; c++) atom->omega[i][c] = eval(p.a[c], t0);
          put(load(L_[i]).transpose() * vec(atom->omega[i]), W_[i]);
        }
      }
    }
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
    const Mat3 L = load(L_[i]);
    Vec3 body[3];
    for (int k = 0; k < r.nang; k++) body[k] = L.transpose() * r.ang[k];
    put(rigid::remove_components(vec(W_[i]), body, r.nang), W_[i]);
  }
}

void FixParmecRigid::half_drift()
{
  // Parmec's unforced first half step: x_{1/2} = x0 + h/2 v0, Λ_{1/2} = Λ0 exp(h/2 Ω0); the spatial ω of the
  // first force evaluation is Λ_{1/2} Ω0 (Q1: Λ_{1/2} (h/2) Ω0)
  const double hh = 0.5 * update->dt;
  for (int i = 0; i < atom->nlocal; i++) {
    if (!(atom->mask[i] & groupbit)) continue;
    for (int c = 0; c < 3; c++) atom->x[i][c] += hh * atom->v[i][c];
    const Vec3 W = vec(W_[i]);
    const Mat3 L = load(L_[i]) * rigid::expmap(hh * W, q3_);
    store(L, L_[i]);
    store_quat(L, atom->quat[i]);
    put(L * (q1_ ? Vec3(hh * W) : W), atom->omega[i]);
  }
}

void FixParmecRigid::final_integrate()
{
  const double h = update->dt;
  const double tn = step_time();
  double g[3] = {0, 0, 0}, dl[3] = {0, 0, 0}, da[3] = {0, 0, 0};
  for (int c = 0; c < 3; c++) {
    if (has_gravity_) g[c] = eval(gravity_[c], tn);
    if (has_damping_) {
      dl[c] = eval(damp_lin_[c], tn);
      da[c] = eval(damp_ang_[c], tn);
    }
  }
  const double tv = q2_ ? tn : tn + h;  // time of a prescribed velocity (Q2: one step late)
  double **x = atom->x, **v = atom->v, **f = atom->f, **omega = atom->omega, **torque = atom->torque;
  const double *rmass = atom->rmass, *radius = atom->radius;
  const int *mask = atom->mask;
  for (int i = 0; i < atom->nlocal; i++) {
    if (!(mask[i] & groupbit)) continue;
    const double m = rmass[i];
    Mat3 J;
    if (J_)
      J = rigid::inertia_from_list(J_[i]);
    else
      J = Mat3::Identity() * (0.4 * m * radius[i] * radius[i]);
    const Mat3 Jinv = J.inverse();
    const Mat3 L = load(L_[i]);
    Vec3 F = vec(f[i]) + m * Vec3(g[0], g[1], g[2]);
    Vec3 T = vec(torque[i]);
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
      F -= m * Vec3(dl[0] * vn[0], dl[1] * vn[1], dl[2] * vn[2]);
      T -= L * J * L.transpose() * Vec3(da[0] * wn[0], da[1] * wn[1], da[2] * wn[2]);
    }
    put(F, f[i]);
    put(T, torque[i]);

    const Vec3 v1 = vn + (h / m) * F;
    const rigid::RotationStep rot = rigid::rotation_step(J, Jinv, L, vec(W_[i]), T, h, q3_);
    for (int c = 0; c < 3; c++) x[i][c] += h * v1[c];
    put(v1, v[i]);
    Vec3 W = rot.W, w = rot.w;
    if (p && p->lin && !p->lin_acc)
      for (int c = 0; c < 3; c++) v[i][c] = eval(p->l[c], tv);
    if (p && p->ang && !p->ang_acc) {
      w = Vec3(eval(p->a[0], tv), eval(p->a[1], tv), eval(p->a[2], tv));
      W = rot.L.transpose() * w;
    }
    store(rot.L, L_[i]);
    put(W, W_[i]);
    put(w, omega[i]);
    store_quat(rot.L, atom->quat[i]);
  }
}

void FixParmecRigid::write_restart(FILE *fp)
{
  if (comm->me == 0) {
    const int n = 1;
    const double data = started_;
    fwrite(&n, sizeof(int), 1, fp);
    fwrite(&data, sizeof(double), 1, fp);
  }
}

void FixParmecRigid::restart(char *buf)
{
  started_ = reinterpret_cast<double *>(buf)[0] != 0.0;
}

static void *create_fix_parmec_rigid(void *lmp, int narg, char **arg)
{
  return new FixParmecRigid(static_cast<LAMMPS *>(lmp), narg, arg);
}
static RegisterStyle reg_fix_parmec_rigid("fix", "parmec/rigid",
                                          "Parmec rigid-body integrator with RESTRAIN, PRESCRIBE, DAMPING, GRAVITY",
                                          create_fix_parmec_rigid);

}  // namespace dembridge
