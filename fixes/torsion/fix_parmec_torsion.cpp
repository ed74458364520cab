// fix parmec/torsion: LAMMPS glue for the Parmec TORSION_SPRING kernels. See fix_parmec_torsion.h for the
// design and doc/fix_parmec_torsion.md for the user syntax.
#include "fix_parmec_torsion.h"
#include "definition_file.h"

#include "style_registry.h"

#include "AxisInertia.h"
#include "TorsionStep.h"

#include "atom.h"
#include "comm.h"
#include "domain.h"
#include "error.h"
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
const char *const kKeywords[] = {"table", "torsion", "file", "history", "start"};

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
ts::Mat3 rotation(const double *q)
{
  const double w = q[0], x = q[1], y = q[2], z = q[3];
  return {w * w + x * x - y * y - z * z, 2.0 * (x * y - w * z),         2.0 * (x * z + w * y),
          2.0 * (x * y + w * z),         w * w - x * x + y * y - z * z, 2.0 * (y * z - w * x),
          2.0 * (x * z - w * y),         2.0 * (y * z + w * x),         w * w - x * x - y * y + z * z};
}

sp::Vec3 apply_t(const ts::Mat3 &m, const sp::Vec3 &v)
{
  return {m[0] * v[0] + m[3] * v[1] + m[6] * v[2], m[1] * v[0] + m[4] * v[1] + m[7] * v[2],
          m[2] * v[0] + m[5] * v[1] + m[8] * v[2]};
}

sp::Vec3 vec(const double *a) { return {a[0], a[1], a[2]}; }

}  // namespace

FixParmecTorsion::FixParmecTorsion(LAMMPS *lmp, int narg, char **arg) : Fix(lmp, narg, arg)
{
  cmd_ = std::string("fix ") + arg[0] + " parmec/torsion";
  if (narg < 4)
    error->all(FLERR, cmd_ + ": expected definitions (table, torsion, file, history, start) after the style name");

  restart_global = 1;
  restart_peratom = 1;
  create_attribute = 1;
  local_flag = 1;
  size_local_cols = kCols;
  size_local_rows = 0;
  local_freq = 1;

  parse(std::vector<std::string>(arg + 3, arg + narg), "command line");
  if (defs_.empty()) error->all(FLERR, cmd_ + ": no torsion spring defined (expected at least one 'torsion' definition)");

  // Resolve table IDs (forward references allowed) and validate each law.
  for (std::size_t s = 0; s < defs_.size(); s++) {
    TorsionDef &d = defs_[s];
    const LawNames &n = names_[s];
    const std::string who = cmd_ + ": torsion spring " + std::to_string(d.id) + ": ";
    auto table = [&](const std::string &id, const std::string &role) -> const sp::SpringTable * {
      auto it = tables_.find(id);
      if (it == tables_.end())
        error->all(FLERR, who + role + " table ID '" + id + "' is not defined (expected the ID of a 'table' definition)");
      return &it->second;
    };
    for (int a = 0; a < 3; a++) {
      if (!n.k[a].empty()) d.law.axis[a].spring = table(n.k[a], std::string("k") + kAxis[a]);
      if (!n.d[a].empty()) d.law.axis[a].damper = table(n.d[a], std::string("d") + kAxis[a]);
    }
    try {
      d.law.validate();
    } catch (std::invalid_argument &e) {
      error->all(FLERR, who + e.what());
    }
    by_part1_[d.tag1].push_back(static_cast<int>(s));
    if (d.tag2 >= 0) has_pairs_ = true;
  }
  names_.clear();
  for (auto &kv : by_part1_) max_per_atom_ = std::max<int>(max_per_atom_, kv.second.size());
  int kmax2 = 1;
  {
    std::unordered_map<tagint, int> touching, as_part2;
    for (const TorsionDef &d : defs_) {
      kmax_ = std::max(kmax_, ++touching[d.tag1]);
      if (d.tag2 >= 0) {
        kmax_ = std::max(kmax_, ++touching[d.tag2]);
        kmax2 = std::max(kmax2, ++as_part2[d.tag2]);
      }
    }
  }
  ordered_ = kmax_ <= kMaxOrdered;
  if (!ordered_) kmax_ = kmax2 = 1;
  comm_reverse = 1 + 4 * kmax2;

  maxexchange = 1 + max_per_atom_ * kSlot;
  grow_arrays(atom->nmax);
  atom->add_callback(Atom::GROW);
  atom->add_callback(Atom::RESTART);

  reference_frames();
  initial_states();

  if (hist_every_ > 0) {
    std::unordered_map<long, int> index;
    for (std::size_t s = 0; s < defs_.size(); s++) index[defs_[s].id] = static_cast<int>(s);
    for (long hid : hist_ids_) {
      if (!index.count(hid))
        error->all(FLERR, cmd_ + ": history: torsion spring ID " + std::to_string(hid) +
                              " is not defined (unknown spring ID)");
      hist_pos_[index[hid]] = static_cast<int>(hist_pos_.size());
    }
    nevery = hist_every_;
    if (comm->me == 0) {
      hist_fp_ = fopen(hist_file_.c_str(), "w");
      if (!hist_fp_) error->one(FLERR, cmd_ + ": history: cannot open file '" + hist_file_ + "' for writing");
      fprintf(hist_fp_, "TIME");
      for (long hid : hist_ids_)
        for (const char *c : {"ROLL", "PITCH", "YAW", "TRQTOT_R", "TRQTOT_P", "TRQTOT_Y", "TRQSPR_R", "TRQSPR_P",
                              "TRQSPR_Y", "XDIR_X", "XDIR_Y", "XDIR_Z", "ZDIR_X", "ZDIR_Y", "ZDIR_Z"})
          fprintf(hist_fp_, ",trq%ld_%s", hid, c);
      fprintf(hist_fp_, "\n");
      fflush(hist_fp_);
    }
  }
}

FixParmecTorsion::~FixParmecTorsion()
{
  atom->delete_callback(id, Atom::GROW);
  atom->delete_callback(id, Atom::RESTART);
  memory->destroy(array_local);
  if (hist_fp_) fclose(hist_fp_);
}

int FixParmecTorsion::setmask()
{
  return POST_FORCE | MIN_POST_FORCE | (hist_every_ > 0 ? END_OF_STEP : 0);
}

// ---------------------------------------------------------------------------------------------------
// parsing

double FixParmecTorsion::number(const std::string &s, const std::string &what, const std::string &where)
{
  double v;
  if (!parse_double(s, v) || !std::isfinite(v))
    error->all(FLERR, cmd_ + " (" + where + "): " + what + ": expected a finite number, got '" + s + "'");
  return v;
}

void FixParmecTorsion::parse(const std::vector<std::string> &tok, const std::string &where)
{
  std::size_t i = 0;
  auto need = [&](std::size_t n, const std::string &what) {
    if (i + n >= tok.size())
      error->all(FLERR, cmd_ + " (" + where + "): '" + tok[i] + "' needs " + what + ", the arguments ended");
  };
  while (i < tok.size()) {
    const std::string kw = tok[i];
    if (kw == "table") {
      need(1, "an ID and values");
      const std::string tid = tok[i + 1];
      if (is_number(tid)) error->all(FLERR, cmd_ + " (" + where + "): table ID '" + tid + "' must not be a number");
      std::vector<double> xy;
      i += 2;
      while (i < tok.size() && is_number(tok[i])) xy.push_back(number(tok[i++], "table " + tid + " value", where));
      const std::string who = cmd_ + " (" + where + "): table " + tid + ": ";
      if (tables_.count(tid)) error->all(FLERR, who + "ID defined twice");
      try {
        tables_.emplace(tid, sp::SpringTable::from_pairs(xy, "values"));
      } catch (std::invalid_argument &e) {
        error->all(FLERR, who + e.what() + " (expected x1 y1 x2 y2 ... with at least 2 points, x strictly increasing)");
      }
    } else if (kw == "torsion") {
      parse_torsion(tok, i, where);
    } else if (kw == "file") {
      need(1, "a file name");
      read_file(tok[i + 1]);
      i += 2;
    } else if (kw == "history") {
      need(2, "a file name, an interval N and torsion spring IDs");
      hist_file_ = tok[i + 1];
      const double every = number(tok[i + 2], "history interval N", where);
      if (every < 1 || every != std::floor(every))
        error->all(FLERR, cmd_ + " (" + where + "): history: interval N must be an integer >= 1, got '" + tok[i + 2] + "'");
      hist_every_ = static_cast<int>(every);
      i += 3;
      while (i < tok.size() && is_number(tok[i]))
        hist_ids_.push_back(std::lround(number(tok[i++], "history torsion spring ID", where)));
      if (hist_ids_.empty())
        error->all(FLERR, cmd_ + " (" + where + "): history: expected at least one torsion spring ID after the interval");
    } else if (kw == "start") {
      need(1, "'lammps' or 'parmec'");
      if (tok[i + 1] == "parmec")
        parmec_start_ = true;
      else if (tok[i + 1] == "lammps")
        parmec_start_ = false;
      else
        error->all(FLERR, cmd_ + " (" + where + "): start: expected 'lammps' or 'parmec', got '" + tok[i + 1] + "'");
      i += 2;
    } else {
      error->all(FLERR, cmd_ + " (" + where + "): unknown keyword '" + kw +
                            "' (expected table, torsion, file, history or start)");
    }
  }
}

void FixParmecTorsion::parse_torsion(const std::vector<std::string> &tok, std::size_t &i, const std::string &where)
{
  // torsion SID I1 I2 zx zy zz xx xy xz [options]
  const std::string ctx = cmd_ + " (" + where + "): torsion";
  std::size_t k = i + 1;
  auto next = [&](const std::string &what) -> const std::string & {
    if (k >= tok.size())
      error->all(FLERR, ctx + ": missing " + what + " (expected: torsion SID part1 part2 zx zy zz xx xy xz [options])");
    return tok[k++];
  };
  auto integer = [&](const std::string &s, const std::string &what) -> long {
    char *end = nullptr;
    const long v = std::strtol(s.c_str(), &end, 10);
    if (s.empty() || *end != '\0') error->all(FLERR, ctx + ": " + what + ": expected an integer, got '" + s + "'");
    return v;
  };
  TorsionDef d;
  LawNames n;
  d.id = integer(next("torsion spring ID"), "torsion spring ID");
  const std::string who = ctx + " " + std::to_string(d.id);
  if (!ids_.insert(d.id).second) error->all(FLERR, who + ": torsion spring ID defined twice");
  d.tag1 = integer(next("part1 atom ID"), "part1 atom ID");
  if (d.tag1 < 1) error->all(FLERR, who + ": part1 atom ID must be >= 1, got " + std::to_string(d.tag1));
  d.tag2 = integer(next("part2 atom ID"), "part2 atom ID");
  if (d.tag2 < 1 && d.tag2 != -1)
    error->all(FLERR, who + ": part2 atom ID must be >= 1 or -1 (anchored in space), got " + std::to_string(d.tag2));
  if (d.tag2 == d.tag1) error->all(FLERR, who + ": part1 and part2 are the same atom");
  sp::Vec3 zdir, xdir;
  for (int c = 0; c < 3; c++) zdir[c] = number(next("zdir component"), "zdir", where);
  for (int c = 0; c < 3; c++) xdir[c] = number(next("xdir component"), "xdir", where);
  try {
    d.input = ts::reference_frame(zdir, xdir);
  } catch (std::invalid_argument &e) {
    error->all(FLERR, who + ": " + e.what());
  }

  std::vector<std::string> cone;
  bool have_cone = false;
  while (k < tok.size() && is_option(tok[k])) {
    const std::string o = tok[k++];
    int a = -1;
    for (int c = 0; c < 3; c++)
      if (o.substr(1) == kAxis[c]) a = c;
    if (o[0] == 'k' && a >= 0) {
      n.k[a] = next(o + " table ID");
      if (is_number(n.k[a])) error->all(FLERR, who + ": " + o + ": expected a table ID, got '" + n.k[a] + "'");
    } else if (o[0] == 'd' && a >= 0) {
      const std::string &v = next(o + " table ID or critical damping ratio");
      if (is_number(v)) {
        const double z = number(v, o + " ratio", where);
        if (z < 0) error->all(FLERR, who + ": " + o + ": critical damping ratio must be >= 0, got " + v);
        d.law.axis[a].ratio = z;
        n.d[a].clear();
      } else {
        n.d[a] = v;
        d.law.axis[a].ratio.reset();
      }
    } else if (o == "cone") {
      have_cone = true;
      cone.clear();
      while (k < tok.size() && !is_option(tok[k]) && !is_keyword(tok[k])) cone.push_back(tok[k++]);
    } else if (o == "refpnt") {
      for (int c = 0; c < 3; c++) d.refpnt[c] = number(next("refpnt component"), "refpnt", where);
      d.has_refpnt = true;
    }
  }
  if (k < tok.size() && !is_keyword(tok[k]))
    error->all(FLERR, who + ": unknown option '" + tok[k] +
                          "' (expected kroll, kpitch, kyaw, droll, dpitch, dyaw, cone or refpnt)");
  if (have_cone) {
    if (cone.empty()) error->all(FLERR, who + ": cone: expected 2 or 3 of roll, pitch, yaw");
    try {
      d.law.cone = ts::parse_cone(cone);
    } catch (std::invalid_argument &e) {
      error->all(FLERR, who + ": " + e.what());
    }
  }
  defs_.push_back(d);
  names_.push_back(n);
  i = k;
}

void FixParmecTorsion::read_file(const std::string &path)
{
  parse(read_definition_words(lmp, path, cmd_), "file " + path);
}

// ---------------------------------------------------------------------------------------------------
// reference frames (kernel doc §5): the input frame expressed in part1's body frame

void FixParmecTorsion::reference_frames()
{
  const std::size_t ns = defs_.size();
  constexpr int kG = 6;  // found1 q1(4) found2
  std::vector<double> g(ns * kG, 0.0), all(ns * kG, 0.0);
  std::unordered_map<tagint, int> local;
  for (int i = 0; i < atom->nlocal; i++) local[atom->tag[i]] = i;
  const bool hasq = atom->quat_flag && atom->quat;
  for (std::size_t s = 0; s < ns; s++) {
    auto it = local.find(defs_[s].tag1);
    if (it != local.end()) {
      g[s * kG] = 1.0;
      if (hasq)
        for (int c = 0; c < 4; c++) g[s * kG + 1 + c] = atom->quat[it->second][c];
      else
        g[s * kG + 1] = 1.0;
    }
    if (defs_[s].tag2 >= 0 && local.count(defs_[s].tag2)) g[s * kG + 5] = 1.0;
  }
  MPI_Allreduce(g.data(), all.data(), static_cast<int>(ns * kG), MPI_DOUBLE, MPI_SUM, world);
  for (std::size_t s = 0; s < ns; s++) {
    TorsionDef &d = defs_[s];
    const double *a = &all[s * kG];
    const std::string who = cmd_ + ": torsion spring " + std::to_string(d.id) + ": ";
    if (a[0] == 0.0)
      error->all(FLERR, who + "part1 atom ID " + std::to_string(d.tag1) + " does not exist (unknown atom ID)");
    if (d.tag2 >= 0 && a[5] == 0.0)
      error->all(FLERR, who + "part2 atom ID " + std::to_string(d.tag2) + " does not exist (unknown atom ID)");
    const ts::Mat3 R = rotation(a + 1);
    d.body.x = apply_t(R, d.input.x);
    d.body.y = apply_t(R, d.input.y);
    d.body.z = apply_t(R, d.input.z);
  }
}

void FixParmecTorsion::initial_states()
{
  for (int i = 0; i < atom->nlocal; i++) {
    slots_[i].clear();
    auto it = by_part1_.find(atom->tag[i]);
    if (it == by_part1_.end()) continue;
    for (int s : it->second) {
      std::vector<double> slot(kSlot, 0.0);
      slot[0] = s;
      ts::TorsionState().pack(&slot[1]);  // angles 0 (fresh state, Q23)
      slots_[i].insert(slots_[i].end(), slot.begin(), slot.end());
    }
  }
}

// ---------------------------------------------------------------------------------------------------
// run-time checks

void FixParmecTorsion::init()
{
  if (update->integrate_style && std::strncmp(update->integrate_style, "respa", 5) == 0)
    error->all(FLERR, cmd_ + " does not support run_style respa (use run_style verlet)");
  if (!atom->quat_flag || !atom->quat)
    error->all(FLERR, cmd_ + ": torsion springs co-rotate with part1 and need per-atom quaternions: use atom_style "
                             "bpm/sphere with fix nve/bpm/sphere");
  if (!atom->omega_flag || !atom->torque_flag)
    error->all(FLERR, cmd_ + ": needs per-atom angular velocity and torque (atom_style bpm/sphere)");
  if (has_pairs_ && atom->map_style == 0)
    error->all(FLERR, cmd_ + " needs an atom map (atom_modify map array or hash) to find part2 atoms");
  if (has_pairs_ && !comm->ghost_velocity)
    error->all(FLERR, cmd_ + ": torsion springs between two atoms need ghost angular velocities: use "
                             "'comm_modify vel yes'");
  for (const TorsionDef &d : defs_)
    if (d.law.needs_axis_inertia() && (!atom->rmass_flag || !atom->radius_flag))
      error->all(FLERR, cmd_ + ": torsion spring " + std::to_string(d.id) +
                            ": a critical damping ratio needs per-atom mass and radius (sphere inertia 0.4 m r^2)");
  bigint mine = 0, total = 0;
  for (int i = 0; i < atom->nlocal; i++) mine += slots_[i].size() / kSlot;
  MPI_Allreduce(&mine, &total, 1, MPI_LMP_BIGINT, MPI_SUM, world);
  if (total != static_cast<bigint>(defs_.size()))
    error->all(FLERR, cmd_ + ": " + std::to_string(total) + " torsion spring states for " +
                          std::to_string(defs_.size()) +
                          " springs (an atom of a spring was deleted, or the restart file does not match)");
}

void FixParmecTorsion::setup(int)
{
  // Rank-independent check: part2 must be within the ghost cutoff of part1 on every decomposition.
  const double cut = comm->get_comm_cutoff();
  const bool periodic = domain->xperiodic || domain->yperiodic || domain->zperiodic;
  double worst = 0.0, gworst = 0.0;
  long wid = -1;
  for (int i = 0; i < atom->nlocal; i++) {
    const std::size_t nsp = slots_[i].size() / kSlot;
    for (std::size_t s = 0; s < nsp; s++) {
      const TorsionDef &d = defs_[static_cast<int>(slots_[i][s * kSlot])];
      if (d.tag2 < 0) continue;
      int k = atom->map(d.tag2);
      if (k < 0) continue;  // reported by evaluate()
      if (periodic) k = domain->closest_image(i, k);
      const double r = sp::norm(vec(atom->x[k]) - vec(atom->x[i]));
      if (r > cut && r > worst) {
        worst = r;
        wid = d.id;
      }
    }
  }
  MPI_Allreduce(&worst, &gworst, 1, MPI_DOUBLE, MPI_MAX, world);
  if (gworst > 0.0) {
    long gid = -1;
    if (worst != gworst) wid = -1;
    MPI_Allreduce(&wid, &gid, 1, MPI_LONG, MPI_MAX, world);
    error->all(FLERR, fmt::format("{}: torsion spring {}: its atoms are {:.6g} apart, farther than the ghost cutoff "
                                  "{:.6g}: raise 'comm_modify cutoff'", cmd_, gid, gworst, cut));
  }
  evaluate(Mode::Setup);
}

void FixParmecTorsion::min_setup(int)
{
  evaluate(Mode::Trial);
}

void FixParmecTorsion::post_force(int)
{
  evaluate(Mode::Commit);
}

void FixParmecTorsion::min_post_force(int)
{
  evaluate(Mode::Trial);
}

void FixParmecTorsion::grow_local(int n)
{
  if (n > maxlocal_) {
    maxlocal_ = std::max(n, 2 * maxlocal_);
    memory->destroy(array_local);
    memory->create(array_local, maxlocal_, kCols, "parmec/torsion:array_local");
  }
}

// One evaluation of every torsion spring owned here. Commit: advance the state (once per step). Trial:
// on a copy. Setup: re-apply the torque of the last committed step (split runs and restarts continue
// bitwise); before any committed step a trial torque ('start lammps') or none ('start parmec').
void FixParmecTorsion::evaluate(Mode mode)
{
  const int nlocal = atom->nlocal;
  const int nall = nlocal + atom->nghost;
  if (static_cast<int>(ccount_.size()) < nall) {
    ccount_.resize(nall);
    cbuf_.resize(std::size_t(nall) * kmax_ * 4);
  }
  std::fill(ccount_.begin(), ccount_.begin() + nall, 0);

  double **omega = atom->omega;
  double **quat = atom->quat;
  const double *rmass = atom->rmass_flag ? atom->rmass : nullptr;
  const double *radius = atom->radius_flag ? atom->radius : nullptr;
  const double dt = update->dt;

  int rows = 0;
  for (int i = 0; i < nlocal; i++) rows += slots_[i].size() / kSlot;
  grow_local(rows);
  size_local_rows = rows;
  int row = 0;

  auto inv_inertia = [&](int i) -> ts::Mat3 {
    const double J = (rmass && radius) ? 0.4 * rmass[i] * radius[i] * radius[i] : 0.0;
    const double inv = J > 0.0 ? 1.0 / J : 0.0;
    return {inv, 0, 0, 0, inv, 0, 0, 0, inv};
  };

  for (int i = 0; i < nlocal; i++) {
    const std::size_t nsp = slots_[i].size() / kSlot;
    for (std::size_t s = 0; s < nsp; s++) {
      double *slot = &slots_[i][s * kSlot];
      const int idx = static_cast<int>(slot[0]);
      const TorsionDef &d = defs_[idx];
      int k = -1;
      if (d.tag2 >= 0) {
        k = atom->map(d.tag2);
        if (k < 0)
          error->one(FLERR, fmt::format("{}: torsion spring {}: part2 atom {} is not available to the owner of part1 "
                                        "atom {} (not a ghost, or lost): raise 'comm_modify cutoff'",
                                        cmd_, d.id, d.tag2, d.tag1));
      }
      ts::TorsionState state;
      state.unpack(slot + 1);
      double t[3] = {0.0, 0.0, 0.0};
      bool apply = true;
      if (mode == Mode::Setup && slot[kValid] != 0.0) {
        for (int c = 0; c < 3; c++) t[c] = slot[kTorque + c];
      } else if (mode == Mode::Setup && parmec_start_) {
        apply = false;
      } else {
        const ts::Mat3 L1 = rotation(quat[i]);
        ts::TorsionStepInput in;
        in.frame = ts::current_frame(d.body, L1);
        in.relative_omega = vec(omega[i]);
        if (k >= 0) in.relative_omega = in.relative_omega - vec(omega[k]);
        in.dt = dt;
        if (d.law.needs_axis_inertia()) {
          const ts::Mat3 W1 = ts::spatial_inverse_inertia(L1, inv_inertia(i));
          if (k >= 0) {
            const ts::Mat3 W2 = ts::spatial_inverse_inertia(rotation(quat[k]), inv_inertia(k));
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

  if (has_pairs_) comm->reverse_comm(this);

  // Sum each atom's contributions in spring order: the result does not depend on the decomposition.
  double **torque = atom->torque;
  std::vector<int> order;
  for (int i = 0; i < nlocal; i++) {
    const int n = ccount_[i];
    if (n == 0) continue;
    const double *e = &cbuf_[std::size_t(i) * kmax_ * 4];
    order.resize(n);
    for (int c = 0; c < n; c++) order[c] = c;
    std::sort(order.begin(), order.end(), [&](int l, int r) { return e[4 * l] < e[4 * r]; });
    double sum[3] = {0, 0, 0};
    for (int c : order)
      for (int m = 0; m < 3; m++) sum[m] += e[4 * c + 1 + m];
    for (int c = 0; c < 3; c++) torque[i][c] += sum[c];
  }
}

void FixParmecTorsion::contribute(int i, int idx, const double *t, double sign)
{
  if (!ordered_) {
    double *e = &cbuf_[std::size_t(i) * 4];
    if (ccount_[i] == 0) std::fill(e, e + 4, 0.0);
    ccount_[i] = 1;
    for (int c = 0; c < 3; c++) e[1 + c] += sign * t[c];
    return;
  }
  if (ccount_[i] >= kmax_) error->one(FLERR, cmd_ + ": internal error: too many torsion contributions on one atom");
  double *e = &cbuf_[(std::size_t(i) * kmax_ + ccount_[i]++) * 4];
  e[0] = idx;
  for (int c = 0; c < 3; c++) e[1 + c] = sign * t[c];
}

int FixParmecTorsion::pack_reverse_comm(int n, int first, double *buf)
{
  int m = 0;
  for (int i = first; i < first + n; i++) {
    buf[m++] = ccount_[i];
    const double *e = &cbuf_[std::size_t(i) * kmax_ * 4];
    for (int c = 0; c < 4 * ccount_[i]; c++) buf[m++] = e[c];
  }
  return m;
}

void FixParmecTorsion::unpack_reverse_comm(int n, int *list, double *buf)
{
  int m = 0;
  for (int i = 0; i < n; i++) {
    const int j = list[i];
    const int cnt = static_cast<int>(buf[m++]);
    if (!ordered_) {
      if (cnt) {
        double *e = &cbuf_[std::size_t(j) * 4];
        if (ccount_[j] == 0) std::fill(e, e + 4, 0.0);
        ccount_[j] = 1;
        for (int c = 1; c < 4; c++) e[c] += buf[m + c];
      }
      m += 4 * cnt;
      continue;
    }
    if (ccount_[j] + cnt > kmax_) error->one(FLERR, cmd_ + ": internal error: too many torsion contributions");
    std::copy(buf + m, buf + m + 4 * cnt, &cbuf_[(std::size_t(j) * kmax_ + ccount_[j]) * 4]);
    ccount_[j] += cnt;
    m += 4 * cnt;
  }
}

// History rows: the values of the step just completed, labelled with the LAMMPS time.
void FixParmecTorsion::end_of_step()
{
  if (hist_every_ <= 0) return;
  const std::size_t nh = hist_ids_.size();
  std::vector<double> vals(kHist * nh, 0.0), all(kHist * nh, 0.0);
  for (int i = 0; i < atom->nlocal; i++) {
    const std::size_t nsp = slots_[i].size() / kSlot;
    for (std::size_t s = 0; s < nsp; s++) {
      const double *slot = &slots_[i][s * kSlot];
      auto it = hist_pos_.find(static_cast<int>(slot[0]));
      if (it == hist_pos_.end()) continue;
      std::copy(slot + 1, slot + 1 + kHist, &vals[kHist * std::size_t(it->second)]);
    }
  }
  MPI_Allreduce(vals.data(), all.data(), static_cast<int>(kHist * nh), MPI_DOUBLE, MPI_SUM, world);
  if (hist_fp_) {
    const double t = update->atime + (update->ntimestep - update->atimestep) * update->dt;
    fprintf(hist_fp_, "%.17g", t);
    for (double v : all) fprintf(hist_fp_, ",%.17g", v);
    fprintf(hist_fp_, "\n");
    fflush(hist_fp_);
  }
}

// ---------------------------------------------------------------------------------------------------
// per-atom storage: migration and restart

void FixParmecTorsion::grow_arrays(int nmax)
{
  slots_.resize(nmax);
}

void FixParmecTorsion::copy_arrays(int i, int j, int)
{
  slots_[j] = slots_[i];
}

void FixParmecTorsion::set_arrays(int i)
{
  slots_[i].clear();
}

int FixParmecTorsion::pack_exchange(int i, double *buf)
{
  buf[0] = static_cast<double>(slots_[i].size());
  std::copy(slots_[i].begin(), slots_[i].end(), buf + 1);
  return 1 + static_cast<int>(slots_[i].size());
}

int FixParmecTorsion::unpack_exchange(int nlocal, double *buf)
{
  const int n = static_cast<int>(buf[0]);
  slots_[nlocal].assign(buf + 1, buf + 1 + n);
  return 1 + n;
}

int FixParmecTorsion::size_restart(int i)
{
  return 2 + static_cast<int>(slots_[i].size());
}

int FixParmecTorsion::maxsize_restart()
{
  return 2 + max_per_atom_ * kSlot;
}

int FixParmecTorsion::pack_restart(int i, double *buf)
{
  const int n = static_cast<int>(slots_[i].size());
  buf[0] = 2 + n;
  buf[1] = n;
  std::copy(slots_[i].begin(), slots_[i].end(), buf + 2);
  return 2 + n;
}

void FixParmecTorsion::unpack_restart(int nlocal, int nth)
{
  double **extra = atom->extra;
  int m = 0;
  for (int k = 0; k < nth; k++) m += static_cast<int>(extra[nlocal][m]);
  const int n = static_cast<int>(extra[nlocal][m + 1]);
  slots_[nlocal].assign(&extra[nlocal][m + 2], &extra[nlocal][m + 2] + n);
  for (int s = 0; s < n / kSlot; s++) {
    const int idx = static_cast<int>(slots_[nlocal][s * kSlot]);
    if (idx < 0 || idx >= static_cast<int>(defs_.size()) || defs_[idx].tag1 != atom->tag[nlocal])
      error->one(FLERR, cmd_ + ": restart file holds torsion spring states that do not match the definitions "
                               "(define the same torsion springs in the same order as before write_restart)");
  }
}

// Global restart: the body-frame reference directions, so that a restarted run does not re-reference the
// springs to the current orientations.
void FixParmecTorsion::write_restart(FILE *fp)
{
  constexpr int kPer = 11;
  std::vector<double> list(1 + kPer * defs_.size());
  list[0] = static_cast<double>(defs_.size());
  for (std::size_t s = 0; s < defs_.size(); s++) {
    const TorsionDef &d = defs_[s];
    double *o = &list[1 + kPer * s];
    o[0] = d.tag1;
    o[1] = d.tag2;
    for (int c = 0; c < 3; c++) {
      o[2 + c] = d.body.x[c];
      o[5 + c] = d.body.y[c];
      o[8 + c] = d.body.z[c];
    }
  }
  if (comm->me == 0) {
    const int size = static_cast<int>(list.size() * sizeof(double));
    fwrite(&size, sizeof(int), 1, fp);
    fwrite(list.data(), sizeof(double), list.size(), fp);
  }
}

void FixParmecTorsion::restart(char *buf)
{
  constexpr int kPer = 11;
  const double *list = reinterpret_cast<const double *>(buf);
  const std::size_t n = static_cast<std::size_t>(list[0]);
  bool match = n == defs_.size();
  for (std::size_t s = 0; match && s < n; s++)
    match = list[1 + kPer * s] == defs_[s].tag1 && list[2 + kPer * s] == defs_[s].tag2;
  if (!match)
    error->all(FLERR, cmd_ + ": the restart file holds different torsion springs (define the same springs in the "
                             "same order as before write_restart)");
  for (std::size_t s = 0; s < n; s++) {
    TorsionDef &d = defs_[s];
    const double *o = &list[1 + kPer * s];
    for (int c = 0; c < 3; c++) {
      d.body.x[c] = o[2 + c];
      d.body.y[c] = o[5 + c];
      d.body.z[c] = o[8 + c];
    }
  }
}

double FixParmecTorsion::memory_usage()
{
  double bytes = cbuf_.capacity() * sizeof(double) + ccount_.capacity() * sizeof(int) +
                 double(maxlocal_) * kCols * sizeof(double);
  for (int i = 0; i < atom->nlocal; i++) bytes += slots_[i].capacity() * sizeof(double);
  return bytes + defs_.size() * sizeof(TorsionDef);
}

static void *create_fix_parmec_torsion(void *lmp, int narg, char **arg)
{
  return new FixParmecTorsion(static_cast<LAMMPS *>(lmp), narg, arg);
}
static RegisterStyle reg_fix_parmec_torsion("fix", "parmec/torsion",
                                            "Parmec TORSION_SPRING: roll/pitch/yaw tables, dampers, cone limits",
                                            create_fix_parmec_torsion);

}  // namespace dembridge
