// fix parmec/granular: see fix_parmec_granular.h and doc/fix_parmec_granular.md.
#include "rank_error.h"
#include "command_args.h"
#include "fix_parmec_granular.h"

#include "style_registry.h"
#include "triangle_contact.h"

#include "atom.h"
#include "comm.h"
#include "error.h"
#include "force.h"
#include "neigh_list.h"
#include "neighbor.h"
#include "modify.h"
#include "pair.h"
#include "update.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <set>
#include <stdexcept>

using namespace LAMMPS_NS;

namespace dembridge {

namespace pc = parmec_contact;
using mesh::Vec3;

namespace {
constexpr double kPi = 3.14159265358979323846;  // contact areas

Vec3 vec(const double *a) { return {a[0], a[1], a[2]}; }

const char *const kExpected = "color, pairing, obstacle, mesh, quirks, tseries, file or start";

struct Term {  // one contact's contribution to its sphere, summed in key order
  int key;
  double f[3], t[3];
};

// A reaction on a MESH body: body index, sphere tag, contact key, force (3), torque about the centre (3).
constexpr int kReaction = 9;

// 'N x1 y1 z1 ... (9N numbers)' of an obstacle or a MESH body
std::vector<mesh::TriangleNodes> read_triangles(state::EntityWords &w)
{
  const long n = w.integer(w.next("triangle count N"), "triangle count N");
  if (n < 1) w.fail("triangle count N must be >= 1, got " + std::to_string(n));
  std::vector<mesh::TriangleNodes> tris;
  for (long t = 0; t < n; t++) {
    mesh::TriangleNodes tri;
    for (int k = 0; k < 9; k++) tri[k / 3][k % 3] = w.number(w.next("triangle coordinate (9 per triangle)"), "triangle coordinate");
    tris.push_back(tri);
  }
  return tris;
}

// 'KW x y z' (a point or a centre), KW at the next word
Vec3 read_point(state::EntityWords &w, const std::string &kw)
{
  w.next(kw);
  Vec3 p{0, 0, 0};
  for (int k = 0; k < 3; k++) p[k] = w.number(w.next(kw + " coordinate"), kw);
  return p;
}

// 'color C | colors C1 ... CN' at the next word: read into colors (n triangles); false if another keyword
bool read_colors(state::EntityWords &w, std::size_t n, std::vector<int> &colors)
{
  const std::string &kw = w.peek();
  if (kw == "color") {
    w.next("color");
    colors.assign(n, static_cast<int>(w.integer(w.next("color value"), "color")));
    return true;
  }
  if (kw != "colors") return false;
  w.next("colors");
  colors.clear();
  for (std::size_t t = 0; t < n; t++) colors.push_back(static_cast<int>(w.integer(w.next("colour per triangle"), "colors")));
  return true;
}

// The words after the n triangles of an obstacle or a MESH body: the colours (required) and the keywords
// `other` reads (it returns false at a word that is none of them, which ends the definition).
template <class Other>
std::vector<int> read_colors_and(state::EntityWords &w, std::size_t n, Other other)
{
  std::vector<int> colors;
  while (w.more())
    if (!read_colors(w, n, colors) && !other(w.peek())) break;
  if (colors.empty()) w.fail("expected 'color C' or 'colors C1 ... CN'");
  return colors;
}

}  // namespace

FixParmecGranular::FixParmecGranular(LAMMPS *lmp, int narg, char **arg) :
    PerAtomStateFix(lmp, narg, arg, kRecord),
    reader_(lmp, cmd_, state::DefinitionReader::kTseries | state::DefinitionReader::kFile | state::DefinitionReader::kStart,
            "obstacle", kExpected)
{
  if (narg < 4) error->all(FLERR, cmd_ + ": expected definitions (" + std::string(kExpected) + ") after the style name");
  if (!atom->radius_flag || !atom->rmass_flag || !atom->omega_flag || !atom->torque_flag)
    error->all(FLERR, cmd_ + " needs per-atom radius, mass, omega and torque (atom_style sphere or bpm/sphere)");
  reader_.parse(std::vector<std::string>(arg + 3, arg + narg), "command line",
                [this](const std::vector<std::string> &tok, std::size_t &i, const std::string &where) {
                  return parse_option(tok, i, where) || parse_pairing(tok, i, where) || parse_obstacle(tok, i, where) ||
                         parse_mesh(tok, i, where);
                });
  build_obstacles();
  build_bodies();
  vector_flag = 1;
  size_vector = 12;
  global_freq = 1;
  extvector = 0;
  maxexchange_dynamic = 1;
  local_output(kCols);
}

// ------------------------------------------------------------------------------------------ parsing

bool FixParmecGranular::parse_option(const std::vector<std::string> &tok, std::size_t &i, const std::string &where)
{
  if (tok[i] == "quirks") {
    quirks_ = reader_.choice(tok, i, where, {"none", "parmec"}) == 1;
    return true;
  }
  if (tok[i] != "color") return false;
  reader_.need(tok, i, 1, "'type' or i_NAME (an integer per-atom property)", where);
  const std::string &c = tok[i + 1];
  if (c != "type" && (c.rfind("i_", 0) != 0 || c.size() < 3))
    error->all(FLERR, cmd_ + " (" + where + "): color: expected 'type' or i_NAME (fix property/atom i_NAME ghost yes), got '" +
                          c + "'");
  color_name_ = c;
  i += 2;
  return true;
}

bool FixParmecGranular::parse_pairing(const std::vector<std::string> &tok, std::size_t &i, const std::string &where)
{
  if (tok[i] != "pairing") return false;
  state::EntityWords w(reader_, tok, i, where,
                       "pairing C1 C2 spring K [damper Z] [friction MUS [MUD]] [kskn R]");
  const long c1 = w.integer(w.next("color1"), "color1");
  const long c2 = w.integer(w.next("color2"), "color2");
  pc::Pairing p;
  if (w.next("spring") != "spring") w.fail("expected 'spring K' after the colours");
  p.spring = w.number(w.next("spring value"), "spring");
  bool mud_given = false;
  while (w.more()) {
    const std::string &kw = w.peek();
    if (kw == "damper") {
      w.next("damper");
      p.damper = w.number(w.next("damper value"), "damper");
    } else if (kw == "friction") {
      w.next("friction");
      p.mu_static = w.number(w.next("friction value"), "friction");
      mud_given = w.more() && args::is_number(w.peek());
      p.mu_dynamic = mud_given ? w.number(w.next("dynamic friction"), "dynamic friction") : p.mu_static;
    } else if (kw == "kskn") {
      w.next("kskn");
      p.kskn = w.number(w.next("kskn value"), "kskn");
    } else {
      break;
    }
  }
  w.check([&] { pairings_.set(static_cast<int>(c1), static_cast<int>(c2), p); });
  return w.accept(i);
}

bool FixParmecGranular::parse_obstacle(const std::vector<std::string> &tok, std::size_t &i, const std::string &where)
{
  if (tok[i] != "obstacle") return false;
  state::EntityWords w(reader_, tok, i, where,
                       "obstacle OID N x1 y1 z1 ... (9N numbers) color C | colors C1 ... CN [point x y z] "
                       "[linear S S S] [angular S S S]");
  ObstacleDef d;
  d.id = w.id(obstacle_ids_);
  d.triangles = read_triangles(w);
  for (int k = 0; k < 6; k++) d.velocity[k] = "0";
  bool have_point = false, have_velocity = false;
  d.colors = read_colors_and(w, d.triangles.size(), [&](const std::string &kw) {
    if (kw == "point") {
      d.point = read_point(w, kw);
      have_point = true;
    } else if (kw == "linear" || kw == "angular") {
      const int off = kw == "linear" ? 0 : 3;
      w.next(kw);
      for (int k = 0; k < 3; k++) d.velocity[off + k] = w.next(kw + " component (a number or a tseries ID)");
      have_velocity = true;
    } else {
      return false;
    }
    return true;
  });
  if (have_velocity && !have_point) w.fail("a moving obstacle needs its reference 'point x y z'");
  d.moving = have_point && have_velocity;
  defs_.push_back(std::move(d));
  return w.accept(i);
}

bool FixParmecGranular::parse_mesh(const std::vector<std::string> &tok, std::size_t &i, const std::string &where)
{
  if (tok[i] != "mesh") return false;
  state::EntityWords w(reader_, tok, i, where,
                       "mesh ATOM-ID N x1 y1 z1 ... (9N numbers, reference configuration) color C | colors C1 ... CN "
                       "center X Y Z");
  MeshDef d;
  d.tag = w.id(mesh_tags_);
  if (d.tag < 1) w.fail("the atom ID of a MESH body must be >= 1, got " + std::to_string(d.tag));
  d.triangles = read_triangles(w);
  bool have_centre = false;
  d.colors = read_colors_and(w, d.triangles.size(), [&](const std::string &kw) {
    if (kw != "center") return false;
    d.centre = read_point(w, kw);
    have_centre = true;
    return true;
  });
  if (!have_centre) w.fail("expected 'center X Y Z' (the body's mass centre in the reference configuration)");
  mesh_defs_.push_back(std::move(d));
  return w.accept(i);
}

void FixParmecGranular::build_obstacles()
{
  int first = 0;
  for (std::size_t o = 0; o < defs_.size(); o++) {
    ObstacleDef &d = defs_[o];
    const std::string who = cmd_ + ": obstacle " + std::to_string(d.id) + ": ";
    try {
      obstacles_.emplace_back(d.triangles, d.colors);
    } catch (std::exception &e) {
      error->all(FLERR, who + e.what());
    }
    std::array<springs::TimeSeries, 6> vel;
    for (int k = 0; k < 6; k++) {
      const std::string &s = d.velocity[k];
      if (args::is_number(s))
        vel[k] = springs::TimeSeries::constant(reader_.number(s, "obstacle velocity", "obstacle " + std::to_string(d.id)));
      else
        vel[k] = *reader_.tseries(s, who, k < 3 ? "linear" : "angular");
    }
    velocity_.push_back(vel);
    if (d.moving) {
      auto comp = [this, o](int off) {
        return [this, o, off](double t) {
          const auto &s = velocity_[o];
          return Vec3{s[off].value_clamped(t), s[off + 1].value_clamped(t), s[off + 2].value_clamped(t)};
        };
      };
      obstacles_.back().set_motion(d.point, comp(0), comp(3));
    }
    first_triangle_.push_back(first);
    first += obstacles_.back().mesh().size();
    d.triangles.clear();
  }
  candidates_.resize(obstacles_.size());
}

void FixParmecGranular::build_bodies()
{
  int first = first_triangle_.empty() ? 0 : first_triangle_.back() + obstacles_.back().mesh().size();
  for (MeshDef &d : mesh_defs_) {
    try {
      bodies_.emplace_back(d.tag, d.triangles, d.colors, d.centre);
    } catch (std::exception &e) {
      error->all(FLERR, cmd_ + ": mesh " + std::to_string(d.tag) + ": " + e.what());
    }
    body_first_.push_back(first);
    first += bodies_.back().surface().mesh().size();
    d.triangles.clear();
  }
  body_candidates_.resize(bodies_.size());
  check_mesh_pairs();
}

// Contact between two MESH bodies is not implemented (nor in Parmec): a pairing that would make two bodies'
// surfaces touch is refused rather than silently giving no contact.
void FixParmecGranular::check_mesh_pairs() const
{
  std::vector<std::set<int>> colors(bodies_.size());
  for (std::size_t a = 0; a < bodies_.size(); a++)
    for (int t = 0; t < bodies_[a].surface().mesh().size(); t++) colors[a].insert(bodies_[a].surface().color(t));
  for (std::size_t a = 0; a < bodies_.size(); a++)
    for (std::size_t b = a + 1; b < bodies_.size(); b++)
      for (int ca : colors[a])
        for (int cb : colors[b])
          if (pairings_.find(ca, cb).touches())
            error->all(FLERR, fmt::format("{}: MESH bodies {} and {}: the pairing of their colours {} and {} has spring "
                                          "> 0, but contact between two MESH bodies is not implemented (out of scope, as "
                                          "in Parmec): give that colour pair spring 0 or use SPHEREs",
                                          cmd_, bodies_[a].tag(), bodies_[b].tag(), ca, cb));
}

// ------------------------------------------------------------------------------------------ set-up

int FixParmecGranular::setmask()
{
  return FixConst::POST_FORCE | FixConst::MIN_POST_FORCE;
}

void FixParmecGranular::init()
{
  check_run_style_and_ghosts("");
  if (!comm->ghost_velocity)
    error->all(FLERR, cmd_ + ": contacts between spheres need ghost velocities: use 'comm_modify vel yes'");
  color_property_ = -1;
  if (color_name_ != "type") {
    int flag = 0, cols = 0;
    color_property_ = atom->find_custom(color_name_.c_str() + 2, flag, cols);
    if (color_property_ < 0 || flag != 0 || cols != 0)
      error->all(FLERR, cmd_ + ": color " + color_name_ + ": no integer per-atom property " + color_name_ +
                            " (expected 'fix property/atom " + color_name_ + " ghost yes')");
  }
  double rmax = 0.0;  // of the spheres that can touch (MESH bodies and colour <= 0 have no sphere shape)
  for (int i = 0; i < atom->nlocal; i++)
    if ((atom->mask[i] & groupbit) && color_of(i) > 0) rmax = std::max(rmax, atom->radius[i]);
  double all = 0.0;
  MPI_Allreduce(&rmax, &all, 1, MPI_DOUBLE, MPI_MAX, world);
  // the full neighbour list spans the pair cutoff (+ skin): it must reach every touching pair
  const double cut = force->pair ? force->pair->cutforce : 0.0;
  if (cut < 2.0 * all)
    error->all(FLERR, fmt::format("{}: the pair cutoff ({}) is below twice the largest radius ({}): define a pair "
                                  "cutoff of at least {} (e.g. 'pair_style zero {}' and 'pair_coeff * *')",
                                  cmd_, cut, all, 2.0 * all, 2.0 * all));
  neighbor->add_request(this, NeighConst::REQ_FULL | NeighConst::REQ_SIZE);
  rigid_ = nullptr;
  if (!bodies_.empty()) {
    const auto rigid = modify->get_fix_by_style("^parmec/rigid$");
    if (rigid.empty())
      error->all(FLERR, cmd_ + ": mesh: MESH bodies need fix parmec/rigid (their surfaces follow the rotation it keeps)");
    rigid_ = rigid.front();
  }
}

void FixParmecGranular::init_list(int, NeighList *ptr)
{
  list_ = ptr;
}

void FixParmecGranular::setup(int)
{
  // 'start parmec' (the Parmec front end): the first forces are those of the first step, as in Parmec
  if (!reader_.parmec_start) evaluate(Mode::Setup);
}

int FixParmecGranular::color_of(int i) const
{
  return color_property_ < 0 ? atom->type[i] : atom->ivector[color_property_][i];
}

// Every rank gets the pose of every MESH body (its owner's x, Λ, v, ω, mass: one allreduce of 20 doubles a
// body, exact since the other ranks add zeros) and places the body's surface at it; the body atoms are not
// spheres (skip).
void FixParmecGranular::place_bodies(std::vector<int> &skip)
{
  constexpr int kPose = pc::BodyPose::kDoubles;
  const int nb = static_cast<int>(bodies_.size());
  std::vector<double> mine(std::size_t(nb) * (kPose + 1), 0.0), all(mine.size());
  for (int b = 0; b < nb; b++) {
    const int i = atom->map(static_cast<tagint>(bodies_[b].tag()));
    if (i < 0 || i >= atom->nlocal) continue;
    if (color_of(i) > 0)
      fail_on_this_rank(lmp, FLERR, fmt::format("{}: mesh {}: the atom of a MESH body must have colour <= 0 (it has no sphere "
                                                "shape), got {}", cmd_, bodies_[b].tag(), color_of(i)));
    if (!(atom->mask[i] & rigid_->groupbit))
      fail_on_this_rank(lmp, FLERR, fmt::format("{}: mesh {}: the body atom is not in the group of fix {} parmec/rigid (its "
                                                "rotation places the surface)", cmd_, bodies_[b].tag(), rigid_->id));
    skip[i] = 1;
    pc::BodyPose pose;
    const double *L = rigid_->array_atom[i];
    for (int k = 0; k < 3; k++) {
      pose.x[k] = atom->x[i][k];
      pose.v[k] = atom->v[i][k];
      pose.w[k] = atom->omega[i][k];
    }
    for (int k = 0; k < 9; k++) pose.lambda[k] = L[k];
    pose.mass = atom->rmass[i];
    double *out = &mine[std::size_t(b) * (kPose + 1)];
    pose.pack(out);
    out[kPose] = 1.0;
  }
  MPI_Allreduce(mine.data(), all.data(), static_cast<int>(mine.size()), MPI_DOUBLE, MPI_SUM, world);
  for (int b = 0; b < nb; b++) {
    const double *in = &all[std::size_t(b) * (kPose + 1)];
    if (in[kPose] != 1.0)
      error->all(FLERR, fmt::format("{}: mesh {}: no atom with this ID (a MESH body is an atom of fix parmec/rigid)",
                                    cmd_, bodies_[b].tag()));
    bodies_[b].place(pc::BodyPose::unpack(in));
  }
}

// The spheres' reactions on the MESH bodies: every rank's entries gathered on every rank and summed per body in
// (sphere tag, contact key) order, so the sum does not depend on which rank holds which sphere; the owner of
// the body atom adds it. Cost per step: one allgather of the counts and one allgatherv of 9 doubles per
// sphere-body contact.
void FixParmecGranular::apply_body_reactions(const std::vector<double> &reactions)
{
  const int n = static_cast<int>(reactions.size());
  std::vector<int> counts(comm->nprocs), displs(comm->nprocs, 0);
  MPI_Allgather(&n, 1, MPI_INT, counts.data(), 1, MPI_INT, world);
  for (int r = 1; r < comm->nprocs; r++) displs[r] = displs[r - 1] + counts[r - 1];
  std::vector<double> all(std::size_t(displs.back()) + counts.back());
  MPI_Allgatherv(reactions.data(), n, MPI_DOUBLE, all.data(), counts.data(), displs.data(), MPI_DOUBLE, world);
  const std::size_t m = all.size() / kReaction;
  std::vector<std::size_t> order(m);
  for (std::size_t k = 0; k < m; k++) order[k] = k;
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    const double *x = &all[a * kReaction], *y = &all[b * kReaction];
    return std::lexicographical_compare(x, x + 3, y, y + 3);
  });
  std::vector<double> sums(bodies_.size() * 6, 0.0);
  for (std::size_t k : order) {
    const double *e = &all[k * kReaction];
    double *out = &sums[static_cast<std::size_t>(e[0]) * 6];
    for (int c = 0; c < 6; c++) out[c] += e[3 + c];
  }
  for (double &v : body_sums_) v = 0.0;
  for (std::size_t b = 0; b < bodies_.size(); b++) {
    for (int c = 0; c < 6; c++) body_sums_[c] += sums[b * 6 + c];
    const int i = atom->map(static_cast<tagint>(bodies_[b].tag()));
    if (i < 0 || i >= atom->nlocal) continue;
    for (int c = 0; c < 3; c++) {
      atom->f[i][c] += sums[b * 6 + c];
      atom->torque[i][c] += sums[b * 6 + 3 + c];
    }
  }
}

// ------------------------------------------------------------------------------------------ contacts

void FixParmecGranular::evaluate(Mode mode)
{
  const bool commit = mode == Mode::Commit;
  const double h = update->dt;
  // The obstacles move at the start of a committed step (not at the end of the previous one), so a setup
  // pass between runs sees the pose of the last committed step and repeats its forces.
  if (commit && !started_) {
    for (auto &o : obstacles_) o.start(clock_, h, quirks_);
    started_ = true;
  } else if (commit) {
    for (auto &o : obstacles_) o.advance(clock_, h);
    clock_ += h;
  }
  double **x = atom->x, **v = atom->v, **omega = atom->omega, **f = atom->f, **torque = atom->torque;
  const double *radius = atom->radius, *rmass = atom->rmass;
  const int *mask = atom->mask;
  const tagint *tag = atom->tag;
  const int nlocal = atom->nlocal;

  std::vector<int> skip(nlocal);
  for (int i = 0; i < nlocal; i++) skip[i] = !(mask[i] & groupbit) || color_of(i) <= 0;
  if (!bodies_.empty()) place_bodies(skip);
  const double reach = quirks_ ? neighbor->skin : 0.0;
  for (std::size_t o = 0; o < obstacles_.size(); o++) candidates_[o].build(obstacles_[o].mesh(), nlocal, x, radius, skip.data(), reach);
  // a MESH body's candidates: its reference triangles (binned once) against the spheres taken to its reference
  // frame; the candidate test is a superset of the contacts in any frame, the contacts are resolved at the pose
  std::vector<double> xref(bodies_.empty() ? 0 : 3 * std::size_t(nlocal));
  std::vector<const double *> xref_of(bodies_.empty() ? 0 : nlocal);
  for (std::size_t b = 0; b < bodies_.size(); b++) {
    for (int i = 0; i < nlocal; i++) {
      const Vec3 r = bodies_[b].to_reference(vec(x[i]));
      std::copy(r.begin(), r.end(), &xref[3 * std::size_t(i)]);
      xref_of[i] = &xref[3 * std::size_t(i)];
    }
    body_candidates_[b].build(bodies_[b].reference_mesh(), nlocal, xref_of.data(), radius, skip.data(), reach);
  }
  // the triangle sets a sphere can touch: the obstacles, then the MESH bodies (keys in this order)
  struct Surface {
    const pc::Obstacle *shape;
    const mesh::MeshNeighbors *cand;
    int first, body;  // body: index in bodies_, -1 for an obstacle
  };
  std::vector<Surface> surfaces;
  for (std::size_t o = 0; o < obstacles_.size(); o++)
    surfaces.push_back({&obstacles_[o], &candidates_[o], first_triangle_[o], -1});
  for (std::size_t b = 0; b < bodies_.size(); b++)
    surfaces.push_back({&bodies_[b].surface(), &body_candidates_[b], body_first_[b], static_cast<int>(b)});
  std::vector<double> reactions;  // kReaction per sphere-body contact

  std::vector<int> slot(nlocal, -1);
  if (list_)
    for (int ii = 0; ii < list_->inum; ii++) slot[list_->ilist[ii]] = ii;

  for (double &c : counts_) c = 0.0;
  std::vector<double> rows;  // local output (kCols per contact)
  std::vector<Term> terms;
  std::vector<double> fresh;  // the contacts kept this step: key, s (3)
  int most = 0;
  for (int i = 0; i < nlocal; i++) {
    if (skip[i]) {
      if (commit && records_.count(i)) records_.clear(i);
      continue;
    }
    terms.clear();
    fresh.clear();
    const int ci = color_of(i);
    const Vec3 xi = vec(x[i]), vi = vec(v[i]), wi = vec(omega[i]);
    // key: the contact's; from: the record holding its state (the key itself, or a contact it continues)
    // keep = false: Parmec's last force of a separating contact (quirks parmec), which is then dropped
    // body: the MESH body that gets the reaction (-1: none); partner: the output's partner column
    auto contact = [&](int key, int from, const pc::Pairing &p, const Vec3 &n, const Vec3 &arm, const Vec3 &vother,
                       double depth, double meff, bool keep, int color2, double area, int body, double partner) {
      if (from == 0) from = key;
      Vec3 s{0.0, 0.0, 0.0};
      for (int r = 0; r < records_.count(i); r++)
        if (records_.key(i, r) == from) {
          const double *rec = records_.record(i, r);
          s = {rec[1], rec[2], rec[3]};
          break;
        }
      const Vec3 vij = mesh::sub(vother, mesh::add(vi, mesh::cross(wi, arm)));
      const pc::ContactOutput out = pc::granular_force(p, {n, vij, depth, meff, h}, s, commit);
      const Vec3 t = mesh::cross(arm, out.f);
      terms.push_back({key, {out.f[0], out.f[1], out.f[2]}, {t[0], t[1], t[2]}});
      if (keep) fresh.insert(fresh.end(), {double(key), s[0], s[1], s[2]});
      if (body >= 0) {  // the opposite force at the contact point, its torque about the body's centre
        const Vec3 fb = mesh::scale(out.f, -1.0);
        const Vec3 tb = mesh::cross(mesh::sub(mesh::add(xi, arm), bodies_[body].pose().x), fb);
        reactions.insert(reactions.end(), {double(body), double(tag[i]), double(key), fb[0], fb[1], fb[2], tb[0], tb[1], tb[2]});
      }
      if (key < 0 || key > tag[i]) {
        const Vec3 point = mesh::add(xi, arm);
        rows.insert(rows.end(), {double(tag[i]), partner, double(ci), double(color2), point[0],
                                 point[1], point[2], depth, out.f[0], out.f[1], out.f[2], out.fn, n[0], n[1], n[2],
                                 out.kn * depth, area});
      }
      if (key > 0) {
        counts_[0] += 0.5;
      } else if (body >= 0) {
        counts_[5] += 1.0;
      } else {
        counts_[1] += 1.0;
        for (int k = 0; k < 3; k++) counts_[2 + k] -= out.f[k];
      }
    };
    auto has_record = [&](int key) {
      for (int r = 0; r < records_.count(i); r++)
        if (records_.key(i, r) == key) return true;
      return false;
    };
    // spheres: Parmec's contact point is the midpoint of the centres, n points from j to i
    if (slot[i] >= 0) {
      const int *jlist = list_->firstneigh[slot[i]];
      const int jnum = list_->numneigh[slot[i]];
      for (int jj = 0; jj < jnum; jj++) {
        const int j = jlist[jj] & NEIGHMASK;
        if (!(mask[j] & groupbit)) continue;
        const int cj = color_of(j);
        if (cj <= 0) continue;
        const pc::Pairing &p = pairings_.find(ci, cj);
        if (!p.touches()) continue;
        const Vec3 xj = vec(x[j]);
        const Vec3 d = mesh::sub(xi, xj);
        const double len = mesh::norm(d);
        const double depth = radius[i] + radius[j] - len;
        if (len == 0.0 || (depth <= 0.0 && !(quirks_ && has_record(static_cast<int>(tag[j]))))) continue;
        const Vec3 n = mesh::scale(d, 1.0 / len);
        const Vec3 point = mesh::scale(mesh::add(xi, xj), 0.5);
        const Vec3 armj = mesh::sub(point, xj);
        const Vec3 vj = mesh::add(vec(v[j]), mesh::cross(vec(omega[j]), armj));
        // contact area: the circle where the two spheres intersect (0 when they only touch)
        const double along = (len * len + radius[i] * radius[i] - radius[j] * radius[j]) / (2.0 * len);
        const double area = kPi * std::max(0.0, radius[i] * radius[i] - along * along);
        contact(static_cast<int>(tag[j]), 0, p, n, mesh::sub(point, xi), vj, depth, pc::effective_mass(rmass[i], rmass[j]),
                depth > 0.0, cj, area, -1, double(tag[j]));
      }
    }
    // obstacles and MESH bodies: the closest point of each touching triangle. A flat surface of several
    // triangles acts once (LIGGGHTS's coplanar rule, as fix wall/gran mesh): a new face contact is not made
    // while a coplanar neighbour of the same surface touches, and it takes over the tangential spring of one
    // that did. Contacts that existed before go first, so an ongoing contact keeps acting. A MESH body's
    // material velocity is v + ω × (p − x) and m_eff = 1/(1/m_i + 1/m_body), as Parmec's particle contacts.
    for (const Surface &sf : surfaces) {
      const pc::Obstacle &ob = *sf.shape;
      const mesh::TriangleMesh &tm = ob.mesh();
      const mesh::MeshNeighbors &cand = *sf.cand;
      const pc::MeshBody *body = sf.body >= 0 ? &bodies_[sf.body] : nullptr;
      const int first = sf.first, last = first + tm.size();
      auto triangle_of = [&](int key) { return -key - 1 - first; };
      auto on_this_obstacle = [&](int key) { return key < 0 && -key - 1 >= first && -key - 1 < last; };
      for (int pass = 0; pass < 2; pass++)
        for (const int *t = cand.begin(i); t != cand.begin(i) + cand.count(i); ++t) {
          const int key = -(first + *t + 1);
          if (has_record(key) != (pass == 0)) continue;
          const pc::Pairing &p = pairings_.find(ci, ob.color(*t));
          if (!p.touches()) continue;
          mesh::TriangleContact c = mesh::resolve_contact(tm, *t, xi, radius[i]);
          if (quirks_) {  // Parmec: every triangle's own closest point (no edge/corner ownership)
            const mesh::TriangleNodes &tn = tm.nodes(*t);
            c.delta = mesh::sub(pc::closest_point_on_triangle(tn[0], tn[1], tn[2], xi), xi);
            c.kind = mesh::ContactKind::Face;
          }
          if (c.kind == mesh::ContactKind::None) continue;
          const double len = mesh::norm(c.delta);
          const double depth = radius[i] - len;
          if (len == 0.0 || (depth <= 0.0 && !(quirks_ && pass == 0))) continue;
          int carry = 0;  // key of a coplanar neighbour's old contact whose spring this one continues
          if (pass == 1 && c.kind == mesh::ContactKind::Face && !quirks_) {  // quirks: a contact per triangle
            bool flat_neighbour_acts = false;
            for (std::size_t r = 0; r < fresh.size(); r += kRecord) {
              const int k2 = static_cast<int>(fresh[r]);
              if (on_this_obstacle(k2) && tm.coplanar_node_neighbors(triangle_of(k2), *t)) flat_neighbour_acts = true;
            }
            if (flat_neighbour_acts) continue;
            for (int r = 0; r < records_.count(i); r++) {
              const int k2 = records_.key(i, r);
              if (on_this_obstacle(k2) && tm.coplanar_node_neighbors(triangle_of(k2), *t)) carry = k2;
            }
          }
          const Vec3 n = mesh::scale(c.delta, -1.0 / len);
          const double area = kPi * std::max(0.0, radius[i] * radius[i] - len * len);  // the sphere's cut by the plane
          const Vec3 at = mesh::add(xi, c.delta);
          if (body)
            contact(key, carry, p, n, c.delta, body->velocity_at(at), depth, pc::effective_mass(rmass[i], body->pose().mass),
                    depth > 0.0, ob.color(*t), area, sf.body, double(body->tag()));
          else
            contact(key, carry, p, n, c.delta, ob.velocity_at(at), depth, rmass[i], depth > 0.0, ob.color(*t), area, -1, -1.0);
        }
    }
    std::sort(terms.begin(), terms.end(), [](const Term &a, const Term &b) { return a.key < b.key; });
    for (const Term &tm : terms)
      for (int k = 0; k < 3; k++) {
        f[i][k] += tm.f[k];
        torque[i][k] += tm.t[k];
      }
    if (commit) {
      records_.clear(i);
      for (std::size_t r = 0; r < fresh.size(); r += kRecord) {
        double *rec = records_.append(i, static_cast<int>(fresh[r]));
        for (int k = 1; k < kRecord; k++) rec[k] = fresh[r + k];
      }
      most = std::max(most, records_.count(i));
    }
  }
  if (commit) maxexchange = std::max(maxexchange, 1 + most * kRecord);
  if (!bodies_.empty()) apply_body_reactions(reactions);
  const int nrows = static_cast<int>(rows.size() / kCols);
  local_rows(nrows);
  for (int r = 0; r < nrows; r++) std::copy_n(rows.data() + std::size_t(r) * kCols, kCols, array_local[r]);
}

double FixParmecGranular::compute_vector(int n)
{
  if (n >= 6) return body_sums_[n - 6];  // already the same on every rank
  double all[6];
  MPI_Allreduce(counts_, all, 6, MPI_DOUBLE, MPI_SUM, world);
  return all[n];
}

// ------------------------------------------------------------------------------------------ fix_modify, restart

// fix_modify ID file FILE: tseries redefined (the front end re-tabulates callbacks for each DEM call).
int FixParmecGranular::modify_param(int narg, char **arg)
{
  if (std::strcmp(arg[0], "file") != 0) return 0;
  if (narg < 2) error->all(FLERR, cmd_ + ": fix_modify file: expected a file name");
  state::DefinitionReader r(lmp, cmd_, state::DefinitionReader::kTseries | state::DefinitionReader::kFile, "obstacle",
                            "tseries or file");
  r.parse({"file", arg[1]}, "fix_modify", [](const std::vector<std::string> &, std::size_t &, const std::string &) {
    return false;
  });
  for (std::size_t o = 0; o < defs_.size(); o++)
    for (int k = 0; k < 6; k++)
      if (const springs::TimeSeries *ts = r.tables.tseries(defs_[o].velocity[k])) velocity_[o][k] = *ts;
  return 2;
}

void FixParmecGranular::write_restart(FILE *fp)
{
  std::vector<double> out{clock_, started_ ? 1.0 : 0.0, double(obstacles_.size())};
  for (const auto &o : obstacles_) {
    const std::vector<double> s = o.save();
    out.push_back(double(s.size()));
    out.insert(out.end(), s.begin(), s.end());
  }
  // MESH bodies are placed from their atoms every step: only their triangle counts (contact keys) are checked
  out.push_back(double(bodies_.size()));
  for (const auto &b : bodies_) out.push_back(double(b.surface().mesh().size()));
  if (comm->me == 0) {
    const int bytes = static_cast<int>(out.size() * sizeof(double));
    fwrite(&bytes, sizeof(int), 1, fp);
    fwrite(out.data(), sizeof(double), out.size(), fp);
  }
}

void FixParmecGranular::restart(char *buf)
{
  const double *list = reinterpret_cast<const double *>(buf);
  clock_ = list[0];
  started_ = list[1] != 0.0;
  if (static_cast<std::size_t>(list[2]) != obstacles_.size())
    error->all(FLERR, fmt::format("{}: the restart file holds {} obstacles, this fix defines {} (define the same obstacles "
                                  "in the same order)", cmd_, static_cast<long>(list[2]), obstacles_.size()));
  std::size_t m = 3;
  for (auto &o : obstacles_) {
    const std::size_t n = static_cast<std::size_t>(list[m++]);
    try {
      o.restore(std::vector<double>(list + m, list + m + n));
    } catch (std::exception &e) {
      error->all(FLERR, cmd_ + ": restart: " + e.what());
    }
    m += n;
  }
  bool same = static_cast<std::size_t>(list[m]) == bodies_.size();
  for (std::size_t b = 0; same && b < bodies_.size(); b++)
    same = static_cast<int>(list[m + 1 + b]) == bodies_[b].surface().mesh().size();
  if (!same)
    error->all(FLERR, cmd_ + ": the restart file holds other MESH bodies than this fix defines (define the same "
                             "'mesh' surfaces in the same order: the contacts refer to their triangles)");
}

static RegisterStyle reg_fix_parmec_granular("fix", "parmec/granular",
                                             "Parmec GRANULAR contact of spheres and OBSTACLE triangle sets",
                                             create_fix<FixParmecGranular>);

}  // namespace dembridge
