#include "fix_move_mesh.h"

#include "fix_mesh_surface.h"
#include "mesh_args.h"
#include "style_registry.h"

#include "comm.h"
#include "error.h"
#include "input.h"
#include "modify.h"
#include "update.h"
#include "variable.h"

#include <cstring>

using namespace LAMMPS_NS;
using namespace LAMMPS_NS::FixConst;

namespace dembridge {

namespace {
constexpr double kTwoPi = 2. * 3.14159265358979323846;
}

FixMoveMesh::FixMoveMesh(LAMMPS *lmp, int narg, char **arg) : Fix(lmp, narg, arg)
{
  const std::string cmd = std::string("fix move/mesh (id ") + id + ")";
  MeshArgs a(lmp, cmd, narg, arg, 3);
  a.expect_keyword("mesh", "fix ID group move/mesh mesh MESHID style args");
  mesh_id_ = a.word("mesh ID");
  mesh_ = FixMeshSurface::find(lmp, mesh_id_, cmd);
  parse_mover(a);
  if (!a.done()) a.fail(std::string("'") + a.peek() + "'", "unexpected argument after the " + kind_ + " arguments");
  // time_integrate stays 0: this fix moves triangles, not the atoms of its group (LIGGGHTS decks give
  // it group all, which would make LAMMPS warn that the atoms are integrated twice).
  restart_global = 1;
}

void FixMoveMesh::parse_mover(MeshArgs &a)
{
  kind_ = a.word("motion style");
  mesh::TriangleMesh &m = mesh_->mesh_for_motion();
  auto harmonics = [&](const std::string &what) {
    a.expect_keyword("order", what);
    const int n = a.integer("order");
    if (n < 1 || n > 30) a.fail("order", "expected 1 <= order <= 30, got " + std::to_string(n));
    mesh::Harmonics h;
    a.expect_keyword("amplitude", what);
    for (int j = 0; j < n; ++j) h.amplitude.push_back(a.number("amplitude " + std::to_string(j + 1)));
    a.expect_keyword("phase", what);
    for (int j = 0; j < n; ++j) h.phase.push_back(a.number("phase " + std::to_string(j + 1)));
    a.expect_keyword("period", what);
    for (int j = 0; j < n; ++j) h.omega.push_back(kTwoPi / a.positive("period " + std::to_string(j + 1)));
    return h;
  };
  if (kind_ == "linear") {
    mover_ = std::make_unique<mesh::LinearMover>(a.vec3("linear velocity"));
  } else if (kind_ == "linear/variable") {
    for (int k = 0; k < 3; ++k) var_[k] = a.variable_name("linear/variable velocity " + std::to_string(k + 1));
    nvar_ = 3;
    auto lin = std::make_unique<mesh::LinearMover>(mesh::Vec3{0.0, 0.0, 0.0});
    linear_ = lin.get();
    mover_ = std::move(lin);
  } else if (kind_ == "wiggle") {
    a.expect_keyword("amplitude", "wiggle amplitude ax ay az period T");
    const mesh::Vec3 amp = a.vec3("wiggle amplitude");
    a.expect_keyword("period", "wiggle amplitude ax ay az period T");
    mover_ = std::make_unique<mesh::WiggleMover>(amp, a.positive("wiggle period"));
  } else if (kind_ == "rotate" || kind_ == "rotate/variable" || kind_ == "riggle") {
    const std::string usage = kind_ == "rotate"            ? "rotate origin px py pz axis ax ay az period T"
                              : kind_ == "rotate/variable" ? "rotate/variable origin px py pz axis ax ay az omega v_name"
                                                           : "riggle origin px py pz axis ax ay az period T amplitude deg";
    a.expect_keyword("origin", usage);
    const mesh::Vec3 origin = a.vec3(kind_ + " origin");
    a.expect_keyword("axis", usage);
    const mesh::Vec3 axis = a.nonzero_vec3(kind_ + " axis");
    if (kind_ == "rotate") {
      a.expect_keyword("period", usage);
      const double period = a.number("rotate period");
      if (period == 0.0) a.fail("rotate period", "expected a non-zero period (negative turns the other way)");
      mover_ = std::make_unique<mesh::RotateMover>(m, origin, axis, kTwoPi / period);
    } else if (kind_ == "rotate/variable") {
      a.expect_keyword("omega", usage);
      var_[0] = a.variable_name("rotate/variable omega");
      nvar_ = 1;
      auto rot = std::make_unique<mesh::RotateMover>(m, origin, axis, 0.0);
      rotate_ = rot.get();
      mover_ = std::move(rot);
    } else {
      a.expect_keyword("period", usage);
      const double period = a.positive("riggle period");
      a.expect_keyword("amplitude", usage);
      mover_ = std::make_unique<mesh::RiggleMover>(origin, axis, period, a.number("riggle amplitude"));
    }
  } else if (kind_ == "viblin") {
    const std::string usage = "viblin axis ax ay az order n amplitude A1..An phase p1..pn period T1..Tn";
    a.expect_keyword("axis", usage);
    const mesh::Vec3 axis = a.nonzero_vec3("viblin axis");
    mover_ = std::make_unique<mesh::ViblinMover>(axis, harmonics(usage));
  } else if (kind_ == "vibrot") {
    const std::string usage = "vibrot origin px py pz axis ax ay az order n amplitude A1..An phase p1..pn period T1..Tn";
    a.expect_keyword("origin", usage);
    const mesh::Vec3 origin = a.vec3("vibrot origin");
    a.expect_keyword("axis", usage);
    const mesh::Vec3 axis = a.nonzero_vec3("vibrot axis");
    mover_ = std::make_unique<mesh::VibrotMover>(origin, axis, harmonics(usage));
  } else {
    a.fail("'" + kind_ + "'", "unknown motion (expected linear, linear/variable, wiggle, riggle, rotate, "
                              "rotate/variable, viblin or vibrot)");
  }
}

int FixMoveMesh::setmask() { return INITIAL_INTEGRATE; }

void FixMoveMesh::init()
{
  const std::string cmd = std::string("fix move/mesh (id ") + id + ")";
  mesh_ = FixMeshSurface::find(lmp, mesh_id_, cmd);
  for (int k = 0; k < nvar_; ++k) {
    ivar_[k] = input->variable->find(var_[k].c_str());
    if (ivar_[k] < 0) error->all(FLERR, cmd + ": variable '" + var_[k] + "' does not exist");
    if (!input->variable->equalstyle(ivar_[k]))
      error->all(FLERR, cmd + ": variable '" + var_[k] + "' is not an equal-style variable");
  }
}

void FixMoveMesh::initial_integrate(int)
{
  const double dt = update->dt;
  time_ += dt;
  mesh::TriangleMesh &m = mesh_->mesh_for_motion();
  if (mesh_->mover_rank(this) == 0) m.zero_velocity();
  if (nvar_ > 0) {
    modify->clearstep_compute();
    if (linear_)
      linear_->set_velocity({input->variable->compute_equal(ivar_[0]), input->variable->compute_equal(ivar_[1]),
                             input->variable->compute_equal(ivar_[2])});
    else
      rotate_->set_omega(input->variable->compute_equal(ivar_[0]));
    modify->addstep_compute(update->ntimestep + 1);
  }
  mover_->step(m, time_, dt);
}

void FixMoveMesh::write_restart(FILE *fp)
{
  if (comm->me != 0) return;
  const int size = sizeof(double);
  fwrite(&size, sizeof(int), 1, fp);
  fwrite(&time_, sizeof(double), 1, fp);
}

void FixMoveMesh::restart(char *buf) { std::memcpy(&time_, buf, sizeof(double)); }

static void *create_fix_move_mesh(void *lmp, int narg, char **arg)
{
  return new FixMoveMesh(static_cast<LAMMPS *>(lmp), narg, arg);
}
static RegisterStyle reg_fix_move_mesh("fix", "move/mesh", "LIGGGHTS-compatible mesh motion", create_fix_move_mesh);

}  // namespace dembridge
