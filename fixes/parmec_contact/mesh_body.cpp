#include "mesh_body.h"

#include <algorithm>

namespace dembridge::parmec_contact {

void BodyPose::pack(double *out) const
{
  for (int k = 0; k < 3; ++k) {
    out[k] = x[k];
    out[12 + k] = v[k];
    out[15 + k] = w[k];
  }
  for (int k = 0; k < 9; ++k) out[3 + k] = lambda[k];
  out[18] = mass;
}

BodyPose BodyPose::unpack(const double *in)
{
  BodyPose p;
  for (int k = 0; k < 3; ++k) {
    p.x[k] = in[k];
    p.v[k] = in[12 + k];
    p.w[k] = in[15 + k];
  }
  for (int k = 0; k < 9; ++k) p.lambda[k] = in[3 + k];
  p.mass = in[18];
  return p;
}

MeshBody::MeshBody(long tag, std::vector<mesh::TriangleNodes> triangles, std::vector<int> colors, const Vec3 &centre) :
    tag_(tag), surface_(triangles, colors), reference_(triangles, std::move(colors)), centre_(centre),
    arms_(std::move(triangles))
{
  for (auto &tri : arms_)
    for (auto &p : tri) p = mesh::sub(p, centre);
  placed_.resize(arms_.size());
  pose_.x = centre;
}

void MeshBody::place(const BodyPose &pose)
{
  // a body at rest keeps its triangles (and the candidate bins built on them)
  const bool same = placed_once_ && pose.x == pose_.x && std::equal(pose.lambda, pose.lambda + 9, pose_.lambda);
  pose_ = pose;
  if (same) return;
  placed_once_ = true;
  const double *L = pose.lambda;
  for (std::size_t t = 0; t < arms_.size(); ++t)
    for (int k = 0; k < 3; ++k) {
      const Vec3 &a = arms_[t][k];
      for (int c = 0; c < 3; ++c) placed_[t][k][c] = pose.x[c] + (L[3 * c] * a[0] + L[3 * c + 1] * a[1] + L[3 * c + 2] * a[2]);
    }
  surface_.place(placed_);
}

Vec3 MeshBody::to_reference(const Vec3 &p) const
{
  const Vec3 d = mesh::sub(p, pose_.x);
  const double *L = pose_.lambda;
  Vec3 r;
  for (int c = 0; c < 3; ++c) r[c] = centre_[c] + (L[c] * d[0] + L[3 + c] * d[1] + L[6 + c] * d[2]);
  return r;
}

Vec3 MeshBody::velocity_at(const Vec3 &p) const
{
  return mesh::add(pose_.v, mesh::cross(pose_.w, mesh::sub(p, pose_.x)));
}

}  // namespace dembridge::parmec_contact
