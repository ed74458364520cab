#include "mbdyn_mesh_driver.h"

#include "fix_mesh_surface.h"
#include "math/rotation.h"

#include "error.h"
#include "lammps.h"

#include <cmath>

namespace dembridge {

namespace {

using V3 = MbdynMeshDriver::V3;
using M9 = MbdynMeshDriver::M9;

using math::axis_angle;  // the math layer (math/rotation.h)
using math::cross;

}  // namespace

void MbdynMeshDriver::attach(LAMMPS_NS::LAMMPS *lmp, const std::string &mesh_id, const std::string &caller)
{
  mesh_ = FixMeshSurface::find(lmp, mesh_id, caller);
  if (!mesh_->stress_on())
    lmp->error->all(FLERR, caller + ": node mesh " + mesh_id + " needs fix mesh/surface/stress (with stress on), "
                                    "which sums the wall contacts' force and moment that go to MBDyn");
  if (mesh_->moving() && !mesh_->driven_externally())
    lmp->error->all(FLERR, caller + ": node mesh " + mesh_id + " is also moved by fix move/mesh; a mesh follows "
                                    "either MBDyn or fix move/mesh");
  mesh_->drive_externally();
}

void MbdynMeshDriver::bind(const V3 &x0, const M9 &R0)
{
  x_ = x0;
  R_ = R0;
  if (point_ < 0) point_ = mesh_->mesh_for_motion().attach_point({x0[0], x0[1], x0[2]});
}

void MbdynMeshDriver::move_to(const V3 &x, const M9 &R, const V3 &v, const V3 &w)
{
  mesh::TriangleMesh &m = mesh_->mesh_for_motion();
  // dR = R R_old^T about the old point, then the translation to the new point
  M9 dR{};
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      for (int k = 0; k < 3; ++k) dR[3 * i + j] += R[3 * i + k] * R_[3 * j + k];
  V3 axis;
  const double angle = axis_angle(dR, axis);
  if (angle != 0.0) m.rotate(angle, {axis[0], axis[1], axis[2]}, {x_[0], x_[1], x_[2]});
  m.translate({x[0] - x_[0], x[1] - x_[1], x[2] - x_[2]});
  x_ = x;
  R_ = R;
  m.zero_velocity();
  for (int t = 0; t < m.size(); ++t)
    for (int k = 0; k < 3; ++k) {
      const mesh::Vec3 &p = m.node(t, k);
      const V3 wxr = cross(w, {p[0] - x[0], p[1] - x[1], p[2] - x[2]});
      m.add_node_velocity(t, k, {v[0] + wxr[0], v[1] + wxr[1], v[2] + wxr[2]});
    }
}

void MbdynMeshDriver::loads(const V3 &x, double *out6) const
{
  // fix mesh/surface/stress: f_ID[1..3] force, [4..6] moment about its reference point, [7..9]
  // that point (it moves with the mesh); collective (MPI sum of the wall contacts so far).
  V3 F, M, r;
  for (int c = 0; c < 3; ++c) {
    F[c] = mesh_->compute_vector(c);
    M[c] = mesh_->compute_vector(3 + c);
    r[c] = mesh_->compute_vector(6 + c) - x[c];
  }
  const V3 rxF = cross(r, F);
  for (int c = 0; c < 3; ++c) {
    out6[c] += F[c];
    out6[3 + c] += M[c] + rxF[c];
  }
}

void MbdynMeshDriver::restart_totals() { mesh_->pre_force(0); }

MbdynMeshDriver::V3 MbdynMeshDriver::tracked_point() const
{
  const mesh::Vec3 &p = mesh_->mesh().attached_point(point_);
  return {p[0], p[1], p[2]};
}

}  // namespace dembridge
