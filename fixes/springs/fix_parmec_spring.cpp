// fix parmec/spring: LAMMPS glue for the Parmec SPRING kernels. See fix_parmec_spring.h for the design
// and doc/fix_parmec_spring.md for the user syntax.
#include "fix_parmec_spring.h"
#include "definition_file.h"

#include "style_registry.h"

#include "CriticalStep.h"
#include "EquivalentMass.h"
#include "SpringStep.h"

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
#include <set>
#include <sstream>
#include <stdexcept>

using namespace LAMMPS_NS;
using namespace LAMMPS_NS::FixConst;
namespace sp = dembridge::springs;

namespace dembridge {

using sp::operator+;
using sp::operator-;
using sp::operator*;

namespace {

constexpr int kState = sp::SpringState::kPackedSize;
constexpr int kForce = 1 + kState;  // offset of the stored force in a slot
constexpr int kValid = kForce + 3;  // 1 once the spring has committed a step
constexpr int kCols = 8;            // id LENGTH STROKE F SF FF SS EQM

const char *const kSpringOptions[] = {"dashpot", "ratio",  "direction", "planar", "plane", "unload",
                                      "ylim",    "inactive", "offset",  "friction", "kskn"};

bool is_spring_option(const std::string &s)
{
  for (const char *o : kSpringOptions)
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

// Rotation matrix (body -> space) of a LAMMPS quaternion (w, x, y, z).
struct Rot {
  double m[3][3];
  static Rot identity() { return {{{1, 0, 0}, {0, 1, 0}, {0, 0, 1}}}; }
  static Rot of(const double *q)
  {
    const double w = q[0], x = q[1], y = q[2], z = q[3];
    Rot r;
    r.m[0][0] = w * w + x * x - y * y - z * z;
    r.m[0][1] = 2.0 * (x * y - w * z);
    r.m[0][2] = 2.0 * (x * z + w * y);
    r.m[1][0] = 2.0 * (x * y + w * z);
    r.m[1][1] = w * w - x * x + y * y - z * z;
    r.m[1][2] = 2.0 * (y * z - w * x);
    r.m[2][0] = 2.0 * (x * z - w * y);
    r.m[2][1] = 2.0 * (y * z + w * x);
    r.m[2][2] = w * w - x * x - y * y + z * z;
    return r;
  }
  sp::Vec3 apply(const sp::Vec3 &v) const
  {
    return {m[0][0] * v[0] + m[0][1] * v[1] + m[0][2] * v[2], m[1][0] * v[0] + m[1][1] * v[1] + m[1][2] * v[2],
            m[2][0] * v[0] + m[2][1] * v[1] + m[2][2] * v[2]};
  }
  sp::Vec3 apply_t(const sp::Vec3 &v) const
  {
    return {m[0][0] * v[0] + m[1][0] * v[1] + m[2][0] * v[2], m[0][1] * v[0] + m[1][1] * v[1] + m[2][1] * v[2],
            m[0][2] * v[0] + m[1][2] * v[1] + m[2][2] * v[2]};
  }
};

sp::Vec3 vec(const double *a) { return {a[0], a[1], a[2]}; }
bool zero(const sp::Vec3 &a) { return a[0] == 0.0 && a[1] == 0.0 && a[2] == 0.0; }

}  // namespace

FixParmecSpring::FixParmecSpring(LAMMPS *lmp, int narg, char **arg) : Fix(lmp, narg, arg)
{
  cmd_ = std::string("fix ") + arg[0] + " parmec/spring";
  if (narg < 4)
    error->all(FLERR, cmd_ + ": expected definitions (table, tseries, spring, file, start) after the style name");

  restart_global = 1;
  restart_peratom = 1;
  create_attribute = 1;
  local_flag = 1;
  size_local_cols = kCols;
  size_local_rows = 0;
  local_freq = 1;
  vector_flag = 1;  // CRITICAL: [min per-spring step, min per-particle step]
  size_vector = 2;
  global_freq = 1;
  extvector = 0;

  std::vector<std::string> tok(arg + 3, arg + narg);
  parse(tok, "command line");
  if (defs_.empty()) error->all(FLERR, cmd_ + ": no spring defined (expected at least one 'spring' definition)");

  // Resolve table/TSERIES IDs and validate each law.
  for (std::size_t s = 0; s < defs_.size(); s++) {
    SpringDef &d = defs_[s];
    const LawNames &n = names_[s];
    const std::string who = cmd_ + ": spring " + std::to_string(d.id) + ": ";
    auto table = [&](const std::string &id, const char *role) -> const sp::SpringTable * {
      auto it = tables_.find(id);
      if (it == tables_.end())
        error->all(FLERR, who + role + " table ID '" + id + "' is not defined (expected the ID of a 'table' definition)");
      return &it->second;
    };
    d.law.spring = table(n.spring, "spring");
    if (!n.dashpot.empty()) d.law.dashpot = table(n.dashpot, "dashpot");
    if (!n.unload.empty()) d.law.unload = table(n.unload, "unload");
    if (!n.offset.empty()) {
      auto it = tseries_.find(n.offset);
      if (it == tseries_.end())
        error->all(FLERR, who + "offset TSERIES ID '" + n.offset +
                              "' is not defined (expected the ID of a 'tseries' definition)");
      try {
        d.law.offset = &it->second.as_table("offset");
      } catch (std::invalid_argument &e) {
        error->all(FLERR, who + "offset " + n.offset + ": " + e.what());
      }
    }
    try {
      d.law.validate();
    } catch (std::invalid_argument &e) {
      std::string used = " (spring table " + n.spring;
      if (!n.dashpot.empty()) used += ", dashpot table " + n.dashpot;
      if (!n.unload.empty()) used += ", unload table " + n.unload;
      if (!n.offset.empty()) used += ", offset tseries " + n.offset;
      error->all(FLERR, who + e.what() + used + ")");
    }
    by_part1_[d.tag1].push_back(static_cast<int>(s));
    if (d.tag2 >= 0) has_pairs_ = true;
  }
  names_.clear();
  for (std::size_t s = 0; s < defs_.size(); s++) id_index_[defs_[s].id] = static_cast<int>(s);
  for (auto &kv : by_part1_) max_per_atom_ = std::max<int>(max_per_atom_, kv.second.size());
  int kmax2 = 1;  // most springs with one atom as part2: only those contributions travel to owners
  {
    std::unordered_map<tagint, int> touching, as_part2;
    for (const SpringDef &d : defs_) {
      kmax_ = std::max(kmax_, ++touching[d.tag1]);
      if (d.tag2 >= 0) {
        kmax_ = std::max(kmax_, ++touching[d.tag2]);
        kmax2 = std::max(kmax2, ++as_part2[d.tag2]);
      }
    }
  }
  // Ordered sums need kmax_ slots per atom (local and ghost) and per reverse-communicated atom; an atom
  // with very many springs (a hub) would make that large, so beyond kMaxOrdered the contributions are
  // summed as they come (results then depend on the decomposition at round-off level).
  ordered_ = kmax_ <= kMaxOrdered;
  if (!ordered_) kmax_ = kmax2 = 1;
  comm_reverse = 1 + 7 * kmax2;

  maxexchange = 1 + max_per_atom_ * kSlot;
  grow_arrays(atom->nmax);
  atom->add_callback(Atom::GROW);
  atom->add_callback(Atom::RESTART);

  reference_geometry();
  initial_states();

  if (hist_every_ > 0) {
    std::unordered_map<long, int> index;
    for (std::size_t s = 0; s < defs_.size(); s++) index[defs_[s].id] = static_cast<int>(s);
    for (long hid : hist_ids_) {
      const int found = index.count(hid) ? index[hid] : -1;
      if (found < 0)
        error->all(FLERR, cmd_ + ": history: spring ID " + std::to_string(hid) + " is not defined");
      hist_pos_[found] = static_cast<int>(hist_pos_.size());
    }
    nevery = hist_every_;
    if (comm->me == 0) {
      hist_fp_ = fopen(hist_file_.c_str(), "w");
      if (!hist_fp_) error->one(FLERR, cmd_ + ": history: cannot open file '" + hist_file_ + "' for writing");
      fprintf(hist_fp_, "TIME");
      for (long hid : hist_ids_)
        for (const char *c : {"LENGTH", "STROKE", "F", "SF", "FF", "SS"}) fprintf(hist_fp_, ",spr%ld_%s", hid, c);
      fprintf(hist_fp_, "\n");
      fflush(hist_fp_);
    }
  }
}

// History rows: the values of the step just completed, labelled with the LAMMPS time.
void FixParmecSpring::end_of_step()
{
  if (hist_every_ <= 0) return;
  const std::size_t nh = hist_ids_.size();
  std::vector<double> vals(6 * nh, 0.0), all(6 * nh, 0.0);
  for (int i = 0; i < atom->nlocal; i++) {
    const std::size_t nsp = slots_[i].size() / kSlot;
    for (std::size_t s = 0; s < nsp; s++) {
      const double *slot = &slots_[i][s * kSlot];
      auto it = hist_pos_.find(static_cast<int>(slot[0]));
      if (it == hist_pos_.end()) continue;
      sp::SpringState st;
      st.unpack(slot + 1);
      double *o = &vals[6 * std::size_t(it->second)];
      o[0] = st.length;
      o[1] = st.stroke;
      o[2] = st.force_total;
      o[3] = st.force_elastic;
      o[4] = st.friction_force;
      o[5] = st.code;
    }
  }
  MPI_Allreduce(vals.data(), all.data(), static_cast<int>(6 * nh), MPI_DOUBLE, MPI_SUM, world);
  if (hist_fp_) {
    const double t = update->atime + (update->ntimestep - update->atimestep) * update->dt;
    fprintf(hist_fp_, "%.17g", t);
    for (double v : all) fprintf(hist_fp_, ",%.17g", v);
    fprintf(hist_fp_, "\n");
    fflush(hist_fp_);
  }
}

FixParmecSpring::~FixParmecSpring()
{
  atom->delete_callback(id, Atom::GROW);
  atom->delete_callback(id, Atom::RESTART);
  memory->destroy(array_local);
  if (hist_fp_) fclose(hist_fp_);
}

int FixParmecSpring::setmask()
{
  return POST_FORCE | MIN_POST_FORCE | (hist_every_ > 0 ? END_OF_STEP : 0);
}

// ---------------------------------------------------------------------------------------------------
// parsing

double FixParmecSpring::number(const std::string &s, const std::string &what, const std::string &where)
{
  double v;
  if (!parse_double(s, v) || !std::isfinite(v))
    error->all(FLERR, cmd_ + " (" + where + "): " + what + ": expected a finite number, got '" + s + "'");
  return v;
}

void FixParmecSpring::parse(std::vector<std::string> tok, const std::string &where)
{
  std::size_t i = 0;
  auto need = [&](std::size_t n, const std::string &what) {
    if (i + n >= tok.size())
      error->all(FLERR, cmd_ + " (" + where + "): '" + tok[i] + "' needs " + what + ", the arguments ended");
  };
  while (i < tok.size()) {
    const std::string kw = tok[i];
    if (kw == "table" || kw == "tseries") {
      need(1, "an ID and values");
      const std::string tid = tok[i + 1];
      if (is_number(tid))
        error->all(FLERR, cmd_ + " (" + where + "): " + kw + " ID '" + tid + "' must not be a number");
      std::vector<double> xy;
      i += 2;
      while (i < tok.size() && is_number(tok[i])) xy.push_back(number(tok[i++], kw + " " + tid + " value", where));
      const std::string who = cmd_ + " (" + where + "): " + kw + " " + tid + ": ";
      if ((kw == "table" ? tables_.count(tid) : tseries_.count(tid)))
        error->all(FLERR, who + "ID defined twice");
      try {
        if (kw == "table") {
          tables_.emplace(tid, sp::SpringTable::from_pairs(xy, "values"));
        } else if (xy.size() == 1) {
          tseries_.emplace(tid, sp::TimeSeries::constant(xy[0]));
        } else {
          tseries_.emplace(tid, sp::TimeSeries::from_pairs(xy));
        }
      } catch (std::invalid_argument &e) {
        error->all(FLERR, who + e.what() + " (expected x1 y1 x2 y2 ... with at least 2 points, x strictly increasing)");
      }
    } else if (kw == "spring") {
      parse_spring(tok, i, where);
    } else if (kw == "file") {
      need(1, "a file name");
      read_file(tok[i + 1]);
      i += 2;
    } else if (kw == "history") {
      need(2, "a file name, an interval N and spring IDs");
      hist_file_ = tok[i + 1];
      const double every = number(tok[i + 2], "history interval N", where);
      if (every < 1 || every != std::floor(every))
        error->all(FLERR, cmd_ + " (" + where + "): history: interval N must be an integer >= 1, got '" + tok[i + 2] + "'");
      hist_every_ = static_cast<int>(every);
      i += 3;
      while (i < tok.size() && is_number(tok[i])) hist_ids_.push_back(std::lround(number(tok[i++], "history spring ID", where)));
      if (hist_ids_.empty())
        error->all(FLERR, cmd_ + " (" + where + "): history: expected at least one spring ID after the interval");
    } else if (kw == "eqm") {
      need(1, "'correct' or 'parmec'");
      if (tok[i + 1] == "parmec")
        q8_arm_ = true;
      else if (tok[i + 1] == "correct")
        q8_arm_ = false;
      else
        error->all(FLERR, cmd_ + " (" + where + "): eqm: expected 'correct' or 'parmec', got '" + tok[i + 1] + "'");
      i += 2;
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
                            "' (expected table, tseries, spring, file, history, start or eqm)");
    }
  }
}

void FixParmecSpring::parse_spring(const std::vector<std::string> &tok, std::size_t &i, const std::string &where)
{
  // spring SID I1 P1 I2 P2 TID [options], P = x y z | centre
  const std::string ctx = cmd_ + " (" + where + "): spring";
  std::size_t k = i + 1;
  auto next = [&](const std::string &what) -> const std::string & {
    if (k >= tok.size())
      error->all(FLERR, ctx + ": missing " + what +
                            " (expected: spring SID part1 x1 y1 z1|centre part2 x2 y2 z2|centre TABLE [options])");
    return tok[k++];
  };
  auto integer = [&](const std::string &s, const std::string &what) -> long {
    char *end = nullptr;
    const long v = std::strtol(s.c_str(), &end, 10);
    if (s.empty() || *end != '\0') error->all(FLERR, ctx + ": " + what + ": expected an integer, got '" + s + "'");
    return v;
  };
  SpringDef d;
  LawNames n;
  d.id = integer(next("spring ID"), "spring ID");
  const std::string who = ctx + " " + std::to_string(d.id);
  if (!spring_ids_.insert(d.id).second) error->all(FLERR, who + ": spring ID defined twice");
  auto point = [&](bool &centre, sp::Vec3 &P, const std::string &what) {
    const std::string &t = next(what);
    if (t == "centre" || t == "center") {
      centre = true;
      return;
    }
    P[0] = number(t, what + " x", where);
    P[1] = number(next(what + " y"), what + " y", where);
    P[2] = number(next(what + " z"), what + " z", where);
  };
  d.tag1 = integer(next("part1 atom ID"), "part1 atom ID");
  if (d.tag1 < 1) error->all(FLERR, who + ": part1 atom ID must be >= 1, got " + std::to_string(d.tag1));
  point(d.centre1, d.P1, "point1");
  d.tag2 = integer(next("part2 atom ID"), "part2 atom ID");
  if (d.tag2 < 1 && d.tag2 != -1)
    error->all(FLERR, who + ": part2 atom ID must be >= 1 or -1 (spatial anchor), got " + std::to_string(d.tag2));
  if (d.tag2 == d.tag1) error->all(FLERR, who + ": part1 and part2 are the same atom");
  point(d.centre2, d.P2, "point2");
  if (d.centre2 && d.tag2 < 0) error->all(FLERR, who + ": point2 of a spatial anchor (part2 = -1) needs coordinates, not 'centre'");
  n.spring = next("spring table ID");
  if (is_spring_option(n.spring) || is_number(n.spring))
    error->all(FLERR, who + ": expected the spring table ID after point2, got '" + n.spring + "'");

  bool have_dir = false, planar = false, plane = false;
  sp::Vec3 dir{};
  while (k < tok.size() && is_spring_option(tok[k])) {
    const std::string o = tok[k++];
    if (o == "dashpot") {
      n.dashpot = next("dashpot table ID");
    } else if (o == "ratio") {
      d.law.damping_ratio = number(next("ratio value"), "ratio", where);
      if (d.law.damping_ratio < 0) error->all(FLERR, who + ": ratio must be >= 0");
    } else if (o == "direction") {
      for (int c = 0; c < 3; c++) dir[c] = number(next("direction component"), "direction", where);
      have_dir = true;
    } else if (o == "planar") {
      planar = true;
    } else if (o == "plane") {
      for (int c = 0; c < 3; c++) d.normal[c] = number(next("plane normal component"), "plane normal", where);
      plane = true;
    } else if (o == "unload") {
      n.unload = next("unload table ID");
    } else if (o == "ylim") {
      d.law.ylim_comp = number(next("ylim compression limit"), "ylim", where);
      d.law.ylim_tens = number(next("ylim tension limit"), "ylim", where);
    } else if (o == "inactive") {
      d.inactive = true;
    } else if (o == "offset") {
      n.offset = next("offset TSERIES ID");
    } else if (o == "friction") {
      d.law.friction = number(next("friction value"), "friction", where);
    } else if (o == "kskn") {
      d.law.kskn = number(next("kskn value"), "kskn", where);
    }
  }
  if (planar && !have_dir) error->all(FLERR, who + ": 'planar' needs 'direction dx dy dz' (the plane normal)");
  try {
    if (plane) {
      d.mode = sp::DirectionMode::Plane;  // direction/planar ignored (spec §2.1)
      d.normal = sp::unit_direction(d.normal, "plane normal");
    } else if (have_dir) {
      d.mode = planar ? sp::DirectionMode::Planar : sp::DirectionMode::Constant;
      d.d = sp::unit_direction(dir, "direction");
    }
  } catch (std::invalid_argument &e) {
    error->all(FLERR, who + ": " + e.what());
  }
  defs_.push_back(d);
  names_.push_back(n);
  i = k;
}

void FixParmecSpring::read_file(const std::string &path)
{
  parse(read_definition_words(lmp, path, cmd_), "file " + path);
}

// ---------------------------------------------------------------------------------------------------
// reference geometry (spec §2.1; kernel doc §5): body-frame arms, anchors, stroke0

void FixParmecSpring::reference_geometry()
{
  // Gather the reference centre (unwrapped) and orientation of every spring's atoms from their owners.
  const std::size_t ns = defs_.size();
  constexpr int kG = 16;  // found1 X1(3) q1(4) found2 X2(3) q2(4)
  std::vector<double> g(ns * kG, 0.0), all(ns * kG, 0.0);
  std::unordered_map<tagint, int> local;
  for (int i = 0; i < atom->nlocal; i++) local[atom->tag[i]] = i;
  const bool hasq = atom->quat_flag && atom->quat;
  auto fill = [&](double *out, int i) {
    out[0] = 1.0;
    double x[3];
    domain->unmap(atom->x[i], atom->image[i], x);
    for (int c = 0; c < 3; c++) out[1 + c] = x[c];
    if (hasq)
      for (int c = 0; c < 4; c++) out[4 + c] = atom->quat[i][c];
    else
      out[4] = 1.0;
  };
  for (std::size_t s = 0; s < ns; s++) {
    auto it = local.find(defs_[s].tag1);
    if (it != local.end()) fill(&g[s * kG], it->second);
    if (defs_[s].tag2 >= 0) {
      it = local.find(defs_[s].tag2);
      if (it != local.end()) fill(&g[s * kG + 8], it->second);
    }
  }
  MPI_Allreduce(g.data(), all.data(), static_cast<int>(ns * kG), MPI_DOUBLE, MPI_SUM, world);

  for (std::size_t s = 0; s < ns; s++) {
    SpringDef &d = defs_[s];
    const double *a = &all[s * kG];
    const std::string who = cmd_ + ": spring " + std::to_string(d.id) + ": ";
    if (a[0] == 0.0)
      error->all(FLERR, who + "part1 atom ID " + std::to_string(d.tag1) + " does not exist (unknown atom ID)");
    if (d.tag2 >= 0 && a[8] == 0.0)
      error->all(FLERR, who + "part2 atom ID " + std::to_string(d.tag2) + " does not exist (unknown atom ID)");
    const sp::Vec3 X1 = vec(a + 1);
    const Rot R1 = Rot::of(a + 4);
    const sp::Vec3 P1 = d.centre1 ? X1 : d.P1;
    d.X1ref = X1;
    auto min_image = [&](sp::Vec3 v) {
      domain->minimum_image(FLERR, v[0], v[1], v[2]);
      return v;
    };
    auto snap = [](sp::Vec3 arm, const sp::Vec3 &X) {
      const double tol = 1e-12 * std::max(1.0, sp::norm(X));
      return sp::norm(arm) <= tol ? sp::Vec3{0, 0, 0} : arm;
    };
    d.arm1 = d.centre1 ? sp::Vec3{0, 0, 0} : R1.apply_t(snap(min_image(P1 - X1), X1));
    if (d.tag2 >= 0) {
      const sp::Vec3 X2 = vec(a + 9);
      const Rot R2 = Rot::of(a + 12);
      // part2's point (or plane point) as seen from P1 through the minimum image
      sp::Vec3 P2 = d.centre2 ? X2 : d.P2;
      P2 = P1 + min_image(P2 - P1);
      const sp::Vec3 X2n = P1 + min_image(X2 - P1);
      d.X2ref = X2n;
      if (d.mode == sp::DirectionMode::Plane) {
        const sp::Vec3 Q = sp::plane_anchor(P1, P2, d.normal);
        d.arm2 = R2.apply_t(snap(Q - X2n, X2n));
        d.nref = R2.apply_t(d.normal);
        d.stroke0 = 0.0;
      } else {
        d.arm2 = (d.centre2 ? sp::Vec3{0, 0, 0} : R2.apply_t(snap(P2 - X2n, X2n)));
        d.stroke0 = sp::reference_stroke0(d.mode, d.d, P1, P2);
      }
    } else {
      if (d.mode == sp::DirectionMode::Plane) {
        d.arm2 = sp::plane_anchor(P1, d.P2, d.normal);
        d.nref = d.normal;
        d.stroke0 = 0.0;
      } else {
        d.arm2 = d.P2;
        d.stroke0 = sp::reference_stroke0(d.mode, d.d, P1, d.P2);
      }
    }
  }
}

void FixParmecSpring::initial_states()
{
  where_dirty_ = true;
  for (int i = 0; i < atom->nlocal; i++) {
    slots_[i].clear();
    auto it = by_part1_.find(atom->tag[i]);
    if (it == by_part1_.end()) continue;
    for (int s : it->second) {
      std::vector<double> slot(kSlot, 0.0);
      slot[0] = s;
      sp::SpringState::initial(defs_[s].law, defs_[s].inactive).pack(&slot[1]);
      slots_[i].insert(slots_[i].end(), slot.begin(), slot.end());
    }
  }
}

// ---------------------------------------------------------------------------------------------------
// run-time checks

void FixParmecSpring::init()
{
  if (update->integrate_style && std::strncmp(update->integrate_style, "respa", 5) == 0)
    error->all(FLERR, cmd_ + " does not support run_style respa (use run_style verlet)");
  if (has_pairs_ && atom->map_style == 0)
    error->all(FLERR, cmd_ + " needs an atom map (atom_modify map array or hash) to find part2 atoms");
  if (has_pairs_ && !comm->ghost_velocity)
    error->all(FLERR, cmd_ + ": springs between two atoms need ghost velocities: use 'comm_modify vel yes'");
  const bool hasq = atom->quat_flag && atom->quat;
  for (const SpringDef &d : defs_) {
    const bool off = !zero(d.arm1) || (d.tag2 >= 0 && !zero(d.arm2));
    const bool moving_plane = d.mode == sp::DirectionMode::Plane && d.tag2 >= 0;
    if ((off || moving_plane) && !hasq)
      error->all(FLERR, cmd_ + ": spring " + std::to_string(d.id) +
                            (off ? ": attachment point away from the atom centre" : ": plane attached to part2") +
                            " rotates with the atom and needs per-atom quaternions: use atom_style bpm/sphere with "
                            "fix nve/bpm/sphere, or attach at the centre ('centre' or the atom's coordinates)");
    if (off && !atom->torque_flag)
      error->all(FLERR, cmd_ + ": spring " + std::to_string(d.id) + ": off-centre attachment needs per-atom torque");
    if (d.law.needs_equivalent_mass() && !atom->rmass_flag && !atom->mass)
      error->all(FLERR, cmd_ + ": spring " + std::to_string(d.id) + ": ratio dashpot needs atom masses");
  }
  // every spring must have exactly one state, held by part1's owner
  bigint mine = 0, total = 0;
  for (int i = 0; i < atom->nlocal; i++) mine += slots_[i].size() / kSlot;
  MPI_Allreduce(&mine, &total, 1, MPI_LMP_BIGINT, MPI_SUM, world);
  if (total != static_cast<bigint>(defs_.size()))
    error->all(FLERR, cmd_ + ": " + std::to_string(total) + " spring states for " + std::to_string(defs_.size()) +
                          " springs (an atom of a spring was deleted, or the restart file does not match)");
}

void FixParmecSpring::setup(int)
{
  cutghost_ = comm->get_comm_cutoff();
  // Rank-independent length check: the centre distance of two connected atoms must not exceed the
  // ghost cutoff, otherwise part2 is not a ghost of part1's owner on some decompositions.
  struct {
    double ratio;
    int index;
  } worst{0.0, -1}, gworst{0.0, -1};
  double len = 0.0;
  for (int i = 0; i < atom->nlocal; i++) {
    const std::size_t nsp = slots_[i].size() / kSlot;
    for (std::size_t s = 0; s < nsp; s++) {
      const int idx = static_cast<int>(slots_[i][s * kSlot]);
      const SpringDef &d = defs_[idx];
      if (d.tag2 < 0) continue;
      const bool periodic = domain->xperiodic || domain->yperiodic || domain->zperiodic;
      int k = atom->map(d.tag2);
      if (k < 0) continue;  // reported below by evaluate() with the atom IDs
      if (periodic) k = domain->closest_image(i, k);
      const double r = sp::norm(vec(atom->x[k]) - vec(atom->x[i]));
      if (r > cutghost_ && r / cutghost_ > worst.ratio) {
        worst.ratio = r / cutghost_;
        worst.index = idx;
        len = r;
      }
    }
  }
  MPI_Allreduce(&worst, &gworst, 1, MPI_DOUBLE_INT, MPI_MAXLOC, world);
  if (gworst.index >= 0) {
    double glen = 0.0;
    if (worst.index != gworst.index) len = 0.0;
    MPI_Allreduce(&len, &glen, 1, MPI_DOUBLE, MPI_MAX, world);
    const SpringDef &d = defs_[gworst.index];
    error->all(FLERR, fmt::format("{}: spring {} between atoms {} and {} is {:.6g} long, longer than the ghost cutoff "
                                  "{:.6g}: raise 'comm_modify cutoff' above the longest spring",
                                  cmd_, d.id, d.tag1, d.tag2, glen, cutghost_));
  }
  evaluate(Mode::Setup);
}

void FixParmecSpring::min_setup(int)
{
  cutghost_ = comm->get_comm_cutoff();
  evaluate(Mode::Trial);
}

void FixParmecSpring::post_force(int)
{
  evaluate(Mode::Commit);
}

void FixParmecSpring::min_post_force(int)
{
  evaluate(Mode::Trial);
}

void FixParmecSpring::grow_local(int n)
{
  if (n > maxlocal_) {
    maxlocal_ = std::max(n, 2 * maxlocal_);
    memory->destroy(array_local);
    memory->create(array_local, maxlocal_, kCols, "parmec/spring:array_local");
  }
}

// One evaluation of every spring owned here. Commit: advance the state (once per step). Trial: on a
// copy (minimisation). Setup: re-apply the force of the last committed step (so split runs and restarts
// continue bitwise); before any committed step a trial force, or none with 'start parmec'.
void FixParmecSpring::evaluate(Mode mode)
{
  const int nlocal = atom->nlocal;
  const int nall = nlocal + atom->nghost;
  if (static_cast<int>(ccount_.size()) < nall) {
    ccount_.resize(nall);
    cbuf_.resize(std::size_t(nall) * kmax_ * 7);
  }
  std::fill(ccount_.begin(), ccount_.begin() + nall, 0);

  double **x = atom->x, **v = atom->v;
  double **omega = atom->omega_flag ? atom->omega : nullptr;
  double **quat = (atom->quat_flag && atom->quat) ? atom->quat : nullptr;
  const double dt = update->dt;
  const double tnow = update->atime + (update->ntimestep - update->atimestep) * dt;
  const sp::Vec3 zero3{0, 0, 0};
  const bool periodic = domain->xperiodic || domain->yperiodic || domain->zperiodic;

  int rows = 0;
  for (int i = 0; i < nlocal; i++) rows += slots_[i].size() / kSlot;
  grow_local(rows);
  size_local_rows = rows;
  int row = 0;

  for (int i = 0; i < nlocal; i++) {
    const std::size_t nsp = slots_[i].size() / kSlot;
    for (std::size_t s = 0; s < nsp; s++) {
      double *slot = &slots_[i][s * kSlot];
      const int idx = static_cast<int>(slot[0]);
      const SpringDef &d = defs_[idx];

      // current points (spec §2.2)
      sp::Vec3 xj;
      if (d.tag2 < 0) {
        double xu[3];
        domain->unmap(x[i], atom->image[i], xu);
        xj = vec(xu);
      } else {
        xj = vec(x[i]);
      }
      const Rot Rj = quat ? Rot::of(quat[i]) : Rot::identity();
      const sp::Vec3 a = zero(d.arm1) ? zero3 : Rj.apply(d.arm1);
      int k = -1;
      sp::Vec3 b = zero3, q, normal = d.nref;
      if (d.tag2 >= 0) {
        k = atom->map(d.tag2);
        if (k < 0)
          error->one(FLERR, fmt::format("{}: spring {}: part2 atom {} is not available to the owner of part1 atom {} "
                                        "(not a ghost, or lost): raise 'comm_modify cutoff' above the longest spring",
                                        cmd_, d.id, d.tag2, d.tag1));
        if (periodic) k = domain->closest_image(i, k);
        const double r = sp::norm(vec(x[k]) - vec(x[i]));
        if (r > cutghost_)
          error->one(FLERR, fmt::format("{}: spring {} between atoms {} and {} is {:.6g} long, longer than the ghost "
                                        "cutoff {:.6g}: raise 'comm_modify cutoff' above the longest spring",
                                        cmd_, d.id, d.tag1, d.tag2, r, cutghost_));
        const Rot Rk = quat ? Rot::of(quat[k]) : Rot::identity();
        b = zero(d.arm2) ? zero3 : Rk.apply(d.arm2);
        q = vec(x[k]) + b;
        if (d.mode == sp::DirectionMode::Plane) normal = Rk.apply(d.nref);
      } else {
        q = d.arm2;
      }

      sp::SpringState state;
      state.unpack(slot + 1);
      sp::Vec3 F = zero3;
      bool apply = true;
      double eqm = -1.0;
      if (mode == Mode::Setup && slot[kValid] != 0.0) {
        F = vec(slot + kForce);
      } else if (mode == Mode::Setup && parmec_start_) {
        apply = false;
      } else {
        sp::SpringKinematics kin;
        kin.p = xj + a;
        kin.q = q;
        kin.normal = normal;
        const sp::Vec3 wj = omega ? vec(omega[i]) : zero3;
        const sp::Vec3 vk = k >= 0 ? vec(v[k]) : zero3;
        const sp::Vec3 wk = (k >= 0 && omega) ? vec(omega[k]) : zero3;
        kin.u = sp::relative_velocity(vec(v[i]), wj, a, k >= 0, vk, wk, b);
        const sp::SpringFrame frame = sp::spring_frame(d.mode, d.d, kin);
        sp::SpringStepInput in;
        in.stroke0 = d.stroke0;
        in.time = tnow - dt;  // Parmec's label t_n of the positions x_{n+1/2} (kernel doc §5)
        in.dt = dt;
        try {
          eqm = spring_eqm(d, i, k, frame.z, q8_arm_);
          in.equivalent_mass = std::isnan(eqm) ? 0.0 : eqm;
          if (state.code >= 0) {
            auto u = unspring_unload_.find(state.code);
            in.unspring_unload = u == unspring_unload_.end() ? nullptr : u->second;
          }
          const sp::SpringForce f = sp::advance_spring(d.law, state, frame, in);
          F = f.on_part1;
        } catch (std::exception &e) {
          error->one(FLERR, fmt::format("{}: spring {}: {}", cmd_, d.id, e.what()));
        }
        if (mode == Mode::Commit) {
          state.pack(slot + 1);
          for (int c = 0; c < 3; c++) slot[kForce + c] = F[c];
          slot[kValid] = 1.0;
        }
      }

      if (apply) {
        const sp::Vec3 ta = sp::cross(a, F);
        contribute(i, idx, F, ta, 1.0);
        if (k >= 0) contribute(k, idx, F, sp::cross(b, F), -1.0);
      }
      double *out = array_local[row++];
      out[0] = static_cast<double>(d.id);
      out[1] = state.length;
      out[2] = state.stroke;
      out[3] = state.force_total;
      out[4] = state.force_elastic;
      out[5] = state.friction_force;
      out[6] = state.code;
      if (eqm < 0.0 && !std::isnan(eqm)) {
        try {
          eqm = spring_eqm(d, i, k, d.mode == sp::DirectionMode::Constant ? d.d : state.direction, q8_arm_);
        } catch (std::exception &e) {
          error->one(FLERR, fmt::format("{}: spring {}: {}", cmd_, d.id, e.what()));
        }
      }
      out[7] = eqm;
    }
  }

  if (has_pairs_) comm->reverse_comm(this);

  // Sum each atom's contributions in spring order: the result does not depend on the decomposition.
  double **f = atom->f;
  double **torque = atom->torque_flag ? atom->torque : nullptr;
  std::vector<int> order;
  for (int i = 0; i < nlocal; i++) {
    const int n = ccount_[i];
    if (n == 0) continue;
    const double *e = &cbuf_[std::size_t(i) * kmax_ * 7];
    order.resize(n);
    for (int c = 0; c < n; c++) order[c] = c;
    std::sort(order.begin(), order.end(), [&](int l, int r) { return e[7 * l] < e[7 * r]; });
    double sum[6] = {0, 0, 0, 0, 0, 0};
    for (int c : order)
      for (int m = 0; m < 6; m++) sum[m] += e[7 * c + 1 + m];
    for (int c = 0; c < 3; c++) f[i][c] += sum[c];
    if (torque)
      for (int c = 0; c < 3; c++) torque[i][c] += sum[3 + c];
  }
}

void FixParmecSpring::contribute(int i, int idx, const sp::Vec3 &F, const sp::Vec3 &T, double sign)
{
  if (!ordered_) {
    double *e = &cbuf_[std::size_t(i) * 7];
    if (ccount_[i] == 0) std::fill(e, e + 7, 0.0);
    ccount_[i] = 1;
    for (int c = 0; c < 3; c++) {
      e[1 + c] += sign * F[c];
      e[4 + c] += sign * T[c];
    }
    return;
  }
  if (ccount_[i] >= kmax_) error->one(FLERR, cmd_ + ": internal error: too many spring contributions on one atom");
  double *e = &cbuf_[(std::size_t(i) * kmax_ + ccount_[i]++) * 7];
  e[0] = idx;
  for (int c = 0; c < 3; c++) {
    e[1 + c] = sign * F[c];
    e[4 + c] = sign * T[c];
  }
}

// CRITICAL (spec §13, kernel doc §5): per spring from the spring's EQM along its current direction
// (Constant/Planar: d; before the first step the eigen branch); per particle from every spring attached
// to it. Collective: every rank gathers the (few) numbers of all springs, then estimates its own atoms.
double FixParmecSpring::compute_vector(int n)
{
  if (crit_step_ != update->ntimestep) critical();
  crit_step_ = update->ntimestep;
  return crit_[n];
}

void FixParmecSpring::critical()
{
  constexpr int kRec = 14;  // tag1 tag2 k_s e dir(3) planar arm1(3) arm2(3)
  const double *rmass = atom->rmass_flag ? atom->rmass : nullptr;
  const double *radius = atom->radius_flag ? atom->radius : nullptr;
  auto mass_of = [&](int i) { return rmass ? rmass[i] : atom->mass[atom->type[i]]; };
  auto inertia_of = [&](int i) { return radius ? 0.4 * mass_of(i) * radius[i] * radius[i] : 0.0; };
  auto body = [&](int i) {
    sp::BodyMass b;
    b.mass = mass_of(i);
    const double J = inertia_of(i), inv = J > 0.0 ? 1.0 / J : 0.0;
    b.inv_inertia = {inv, 0, 0, 0, inv, 0, 0, 0, inv};
    return b;
  };
  std::vector<double> mine;
  double hs = INFINITY;
  for (int i = 0; i < atom->nlocal; i++) {
    const std::size_t nsp = slots_[i].size() / kSlot;
    for (std::size_t s = 0; s < nsp; s++) {
      const double *slot = &slots_[i][s * kSlot];
      const SpringDef &d = defs_[static_cast<int>(slot[0])];
      sp::SpringState st;
      st.unpack(slot + 1);
      const bool fixed_dir = d.mode == sp::DirectionMode::Constant;
      const sp::Vec3 zdir = fixed_dir ? d.d : st.direction;
      const sp::BodyMass b1 = body(i);
      double m_s;
      int k = -1;
      if (d.tag2 >= 0) {
        k = atom->map(d.tag2);
        if (k < 0)
          error->one(FLERR, fmt::format("{}: CRITICAL: spring {}: part2 atom {} is not available (run at least "
                                        "'run 0' first, or raise 'comm_modify cutoff')", cmd_, d.id, d.tag2));
        const sp::BodyMass b2 = body(k);
        m_s = sp::equivalent_mass(b1, d.arm1, &b2, d.arm2, zdir);
      } else {
        m_s = sp::equivalent_mass(b1, d.arm1, nullptr, {0, 0, 0}, zdir);
      }
      hs = std::min(hs, sp::spring_critical(d.law, m_s).step);
      const bool planar = d.mode == sp::DirectionMode::Planar;
      const sp::Vec3 adir = planar ? d.d : zdir;
      const double rec[kRec] = {double(d.tag1), double(d.tag2), d.law.spring->max_abs_slope(),
                                sp::spring_max_damping(d.law, m_s), adir[0], adir[1], adir[2], planar ? 1.0 : 0.0,
                                d.arm1[0], d.arm1[1], d.arm1[2], d.arm2[0], d.arm2[1], d.arm2[2]};
      mine.insert(mine.end(), rec, rec + kRec);
    }
  }
  int n = static_cast<int>(mine.size());
  std::vector<int> counts(comm->nprocs), displs(comm->nprocs, 0);
  MPI_Allgather(&n, 1, MPI_INT, counts.data(), 1, MPI_INT, world);
  for (int p = 1; p < comm->nprocs; p++) displs[p] = displs[p - 1] + counts[p - 1];
  std::vector<double> all(displs.back() + counts.back());
  MPI_Allgatherv(mine.data(), n, MPI_DOUBLE, all.data(), counts.data(), displs.data(), MPI_DOUBLE, world);

  std::unordered_map<tagint, sp::ParticleCritical> particles;
  std::unordered_map<tagint, int> owned;
  for (int i = 0; i < atom->nlocal; i++) owned[atom->tag[i]] = i;
  for (std::size_t r = 0; r + kRec <= all.size(); r += kRec) {
    const double *e = &all[r];
    const sp::Vec3 dir{e[4], e[5], e[6]};
    for (int side = 0; side < 2; side++) {
      const tagint t = static_cast<tagint>(e[side]);
      if (t < 0 || !owned.count(t)) continue;
      particles[t].add_spring(e[2], e[3], dir, e[7] != 0.0, {e[8 + 3 * side], e[9 + 3 * side], e[10 + 3 * side]});
    }
  }
  double hp = INFINITY;
  for (auto &kv : particles) {
    const int i = owned[kv.first];
    const double J = inertia_of(i) > 0.0 ? inertia_of(i) : 1.0;
    hp = std::min(hp, kv.second.estimate(mass_of(i), {J, 0, 0, 0, J, 0, 0, 0, J}).step);
  }
  MPI_Allreduce(&hs, &crit_[0], 1, MPI_DOUBLE, MPI_MIN, world);
  MPI_Allreduce(&hp, &crit_[1], 1, MPI_DOUBLE, MPI_MIN, world);
}

int FixParmecSpring::pack_reverse_comm(int n, int first, double *buf)
{
  int m = 0;
  for (int i = first; i < first + n; i++) {
    buf[m++] = ccount_[i];
    const double *e = &cbuf_[std::size_t(i) * kmax_ * 7];
    for (int c = 0; c < 7 * ccount_[i]; c++) buf[m++] = e[c];
  }
  return m;
}

void FixParmecSpring::unpack_reverse_comm(int n, int *list, double *buf)
{
  int m = 0;
  for (int i = 0; i < n; i++) {
    const int j = list[i];
    const int cnt = static_cast<int>(buf[m++]);
    if (!ordered_) {
      if (cnt) {
        double *e = &cbuf_[std::size_t(j) * 7];
        if (ccount_[j] == 0) std::fill(e, e + 7, 0.0);
        ccount_[j] = 1;
        for (int c = 1; c < 7; c++) e[c] += buf[m + c];
      }
      m += 7 * cnt;
      continue;
    }
    if (ccount_[j] + cnt > kmax_) error->one(FLERR, cmd_ + ": internal error: too many spring contributions");
    std::copy(buf + m, buf + m + 7 * cnt, &cbuf_[(std::size_t(j) * kmax_ + ccount_[j]) * 7]);
    ccount_[j] += cnt;
    m += 7 * cnt;
  }
}

// ---------------------------------------------------------------------------------------------------
// per-atom storage: migration and restart

void FixParmecSpring::grow_arrays(int nmax)
{
  slots_.resize(nmax);
  nmax_ = nmax;
}

void FixParmecSpring::copy_arrays(int i, int j, int)
{
  slots_[j] = slots_[i];
  where_dirty_ = true;
}

void FixParmecSpring::set_arrays(int i)
{
  slots_[i].clear();
  where_dirty_ = true;
}

int FixParmecSpring::pack_exchange(int i, double *buf)
{
  buf[0] = static_cast<double>(slots_[i].size());
  std::copy(slots_[i].begin(), slots_[i].end(), buf + 1);
  return 1 + static_cast<int>(slots_[i].size());
}

int FixParmecSpring::unpack_exchange(int nlocal, double *buf)
{
  const int n = static_cast<int>(buf[0]);
  slots_[nlocal].assign(buf + 1, buf + 1 + n);
  where_dirty_ = true;
  return 1 + n;
}

int FixParmecSpring::size_restart(int i)
{
  return 2 + static_cast<int>(slots_[i].size());
}

int FixParmecSpring::maxsize_restart()
{
  return 2 + max_per_atom_ * kSlot;
}

int FixParmecSpring::pack_restart(int i, double *buf)
{
  const int n = static_cast<int>(slots_[i].size());
  buf[0] = 2 + n;
  buf[1] = n;
  std::copy(slots_[i].begin(), slots_[i].end(), buf + 2);
  return 2 + n;
}

void FixParmecSpring::unpack_restart(int nlocal, int nth)
{
  double **extra = atom->extra;
  int m = 0;
  for (int k = 0; k < nth; k++) m += static_cast<int>(extra[nlocal][m]);
  const int n = static_cast<int>(extra[nlocal][m + 1]);
  slots_[nlocal].assign(&extra[nlocal][m + 2], &extra[nlocal][m + 2] + n);
  where_dirty_ = true;
  for (int s = 0; s < n / kSlot; s++) {
    const int idx = static_cast<int>(slots_[nlocal][s * kSlot]);
    if (idx < 0 || idx >= static_cast<int>(defs_.size()) || defs_[idx].tag1 != atom->tag[nlocal])
      error->one(FLERR, cmd_ + ": restart file holds spring states that do not match the spring definitions "
                               "(define the same springs in the same order as before write_restart)");
  }
}

// Global restart: the reference geometry, so that a restarted run does not re-reference the springs
// to the current positions.
void FixParmecSpring::write_restart(FILE *fp)
{
  constexpr int kPer = 18;
  std::vector<double> list(1 + kPer * defs_.size());
  list[0] = -static_cast<double>(defs_.size());  // negative: 18 values per spring (with reference centres)
  for (std::size_t s = 0; s < defs_.size(); s++) {
    const SpringDef &d = defs_[s];
    double *o = &list[1 + kPer * s];
    o[0] = d.tag1;
    o[1] = d.tag2;
    for (int c = 0; c < 3; c++) {
      o[2 + c] = d.arm1[c];
      o[5 + c] = d.arm2[c];
      o[8 + c] = d.nref[c];
    }
    o[11] = d.stroke0;
    for (int c = 0; c < 3; c++) {
      o[12 + c] = d.X1ref[c];
      o[15 + c] = d.X2ref[c];
    }
  }
  if (comm->me == 0) {
    const int size = static_cast<int>(list.size() * sizeof(double));
    fwrite(&size, sizeof(int), 1, fp);
    fwrite(list.data(), sizeof(double), list.size(), fp);
  }
}

void FixParmecSpring::restart(char *buf)
{
  const double *list = reinterpret_cast<const double *>(buf);
  const int kPer = list[0] < 0 ? 18 : 12;  // 12: files written before the reference centres were stored
  const std::size_t n = static_cast<std::size_t>(std::fabs(list[0]));
  bool match = n == defs_.size();
  for (std::size_t s = 0; match && s < n; s++)
    match = list[1 + kPer * s] == defs_[s].tag1 && list[2 + kPer * s] == defs_[s].tag2;
  if (!match)
    error->all(FLERR, cmd_ + ": the restart file holds different springs (define the same springs in the same "
                             "order as before write_restart)");
  for (std::size_t s = 0; s < n; s++) {
    SpringDef &d = defs_[s];
    const double *o = &list[1 + kPer * s];
    for (int c = 0; c < 3; c++) {
      d.arm1[c] = o[2 + c];
      d.arm2[c] = o[5 + c];
      d.nref[c] = o[8 + c];
    }
    d.stroke0 = o[11];
    if (kPer == 18)
      for (int c = 0; c < 3; c++) {
        d.X1ref[c] = o[12 + c];
        d.X2ref[c] = o[15 + c];
      }
    else if (q8_arm_)
      error->all(FLERR, cmd_ + ": 'eqm parmec' needs the reference centres, which this (older) restart file "
                               "does not hold");
  }
  geometry_from_restart_ = true;
}

// EQM (spec §12) of spring d along dir (zero: largest point mass) with the sphere inertia 0.4 m r^2
// of its atoms i (part1) and k (part2, or -1). q8: Parmec's spring-force arm 2X - P (quirk Q8).
double FixParmecSpring::spring_eqm(const SpringDef &d, int i, int k, const sp::Vec3 &dir, bool q8) const
{
  const double *rmass = atom->rmass_flag ? atom->rmass : nullptr;
  const double *radius = atom->radius_flag ? atom->radius : nullptr;
  if (!rmass && !atom->mass) return NAN;  // no masses: EQM undefined (a ratio dashpot is an ERROR in init)
  auto body = [&](int j, const sp::Vec3 &X) {
    sp::BodyMass b;
    b.mass = rmass ? rmass[j] : atom->mass[atom->type[j]];
    const double J = radius ? 0.4 * b.mass * radius[j] * radius[j] : 0.0;
    const double inv = J > 0.0 ? 1.0 / J : 0.0;
    b.inv_inertia = {inv, 0, 0, 0, inv, 0, 0, 0, inv};
    if (q8) b.centre = X;
    return b;
  };
  if (!q8 && !zero(dir)) {
    // isotropic inertia: d^T M^-1 d = |d|^2/m + (|A|^2 |d|^2 - (A.d)^2)/J per body (the kernel's
    // equivalent_mass without the 3x3 matrices; equal to round-off)
    const double dd = sp::dot(dir, dir);
    double lambda = 0.0;
    auto add = [&](int j, const sp::Vec3 &A) {
      const double m = rmass ? rmass[j] : atom->mass[atom->type[j]];
      const double J = radius ? 0.4 * m * radius[j] * radius[j] : 0.0;
      lambda += dd / m;
      if (J > 0.0) {
        const double ad = sp::dot(A, dir);
        lambda += (sp::dot(A, A) * dd - ad * ad) / J;
      }
    };
    add(i, d.arm1);
    if (k >= 0) add(k, d.arm2);
    if (!(lambda > 0.0)) throw std::invalid_argument("EQM: the inverse mass matrix is not positive along the direction");
    return 1.0 / lambda;
  }
  // Correct arm: centre 0, point = body-frame arm (A = -arm). Q8: centre X0, point X0 + arm.
  const sp::BodyMass b1 = body(i, d.X1ref);
  const sp::Vec3 p1 = q8 ? d.X1ref + d.arm1 : d.arm1;
  const auto arm = q8 ? sp::EqmArm::ParmecQ8 : sp::EqmArm::Correct;
  if (k >= 0) {
    const sp::BodyMass b2 = body(k, d.X2ref);
    return sp::equivalent_mass(b1, p1, &b2, q8 ? d.X2ref + d.arm2 : d.arm2, dir, arm);
  }
  return sp::equivalent_mass(b1, p1, nullptr, {0, 0, 0}, dir, arm);
}

int FixParmecSpring::spring_index(long spring_id) const
{
  auto it = id_index_.find(spring_id);
  return it == id_index_.end() ? -1 : it->second;
}

// The slot of a spring whose state this rank owns, or null. The (spring -> atom, slot) index is rebuilt
// after atoms were exchanged, sorted or restarted (O(local springs)), so lookups are O(1) otherwise.
const double *FixParmecSpring::owned_slot(int spring) const
{
  if (spring < 0 || spring >= static_cast<int>(defs_.size())) return nullptr;
  auto *self = const_cast<FixParmecSpring *>(this);
  auto valid = [&](const std::pair<int, int> &w) {
    return w.first >= 0 && w.first < atom->nlocal && (w.second + 1) * kSlot <= int(slots_[w.first].size()) &&
        static_cast<int>(slots_[w.first][w.second * kSlot]) == spring;
  };
  if (!where_dirty_ && where_.size() == defs_.size()) {
    const auto &w = where_[spring];
    if (w.first < 0) return nullptr;
    if (valid(w)) return &slots_[w.first][w.second * kSlot];
  }
  self->where_.assign(defs_.size(), {-1, -1});
  for (int i = 0; i < atom->nlocal; i++) {
    const int nsp = static_cast<int>(slots_[i].size()) / kSlot;
    for (int s = 0; s < nsp; s++) self->where_[static_cast<int>(slots_[i][s * kSlot])] = {i, s};
  }
  self->where_dirty_ = false;
  const auto &w = where_[spring];
  return w.first >= 0 ? &slots_[w.first][w.second * kSlot] : nullptr;
}

namespace {
double state_entity(const sp::SpringState &st, FixParmecSpring::Entity e)
{
  switch (e) {
    case FixParmecSpring::Entity::Length: return st.length;
    case FixParmecSpring::Entity::Stroke: return st.stroke;
    case FixParmecSpring::Entity::F: return st.force_total;
    case FixParmecSpring::Entity::SF: return st.force_elastic;
    case FixParmecSpring::Entity::FF: return st.friction_force;
    case FixParmecSpring::Entity::SS: return st.code;
    default: return NAN;
  }
}
}  // namespace

double FixParmecSpring::entity_value(int spring, Entity e) const
{
  if (e == Entity::EQM) {  // from the output rows of the last evaluation
    if (spring < 0 || spring >= static_cast<int>(defs_.size())) return NAN;
    for (int r = 0; r < size_local_rows && r < maxlocal_; r++)
      if (array_local[r][0] == static_cast<double>(defs_[spring].id)) return array_local[r][7];
    return NAN;
  }
  const double *slot = owned_slot(spring);
  if (!slot) return NAN;
  sp::SpringState st;
  st.unpack(slot + 1);
  return state_entity(st, e);
}

void FixParmecSpring::gather_entity(Entity e, std::vector<double> &out)
{
  std::vector<double> mine(defs_.size(), 0.0);
  if (e == Entity::EQM) {
    for (int r = 0; r < size_local_rows && r < maxlocal_; r++) {
      auto it = id_index_.find(std::lround(array_local[r][0]));
      if (it != id_index_.end()) mine[it->second] = array_local[r][7];
    }
  } else {
    sp::SpringState st;
    for (int i = 0; i < atom->nlocal; i++) {
      const std::size_t nsp = slots_[i].size() / kSlot;
      for (std::size_t s = 0; s < nsp; s++) {
        const double *slot = &slots_[i][s * kSlot];
        st.unpack(slot + 1);
        mine[static_cast<int>(slot[0])] = state_entity(st, e);
      }
    }
  }
  out.assign(defs_.size(), 0.0);
  MPI_Allreduce(mine.data(), out.data(), static_cast<int>(mine.size()), MPI_DOUBLE, MPI_SUM, world);
}

bool FixParmecSpring::set_state_code(int spring, int code)
{
  if (code < sp::kRegular) error->one(FLERR, cmd_ + ": set_state_code: code must be >= -3");
  double *slot = const_cast<double *>(owned_slot(spring));
  if (!slot) return false;
  sp::SpringState st;
  st.unpack(slot + 1);
  st.code = code;
  st.pack(slot + 1);
  return true;
}

void FixParmecSpring::set_unspring_unload(int code, const sp::SpringTable *curve)
{
  if (code < 0) error->all(FLERR, cmd_ + ": set_unspring_unload: code must be >= 0");
  unspring_unload_[code] = curve;
}

double FixParmecSpring::memory_usage()
{
  double bytes = cbuf_.capacity() * sizeof(double) + ccount_.capacity() * sizeof(int) + double(maxlocal_) * kCols * sizeof(double);
  for (int i = 0; i < atom->nlocal; i++) bytes += slots_[i].capacity() * sizeof(double);
  return bytes + defs_.size() * sizeof(SpringDef);
}

static void *create_fix_parmec_spring(void *lmp, int narg, char **arg)
{
  return new FixParmecSpring(static_cast<LAMMPS *>(lmp), narg, arg);
}
static RegisterStyle reg_fix_parmec_spring("fix", "parmec/spring",
                                           "Parmec SPRING model: tables, dashpots, unload/ylim, offsets, friction",
                                           create_fix_parmec_spring);

}  // namespace dembridge
