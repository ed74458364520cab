// The contact surface of a Parmec MESH particle (issue 13): its boundary triangles, coloured per triangle,
// given in the body's reference configuration (rotation Λ = I, mass centre X) and placed at x + Λ(P − X)
// from the body's current pose (fix parmec/rigid's x and Λ, as Parmec moves a mesh with its particle).
// Spheres touching it use the obstacle machinery (obstacle.h) with the body's material velocity
// v + ω × (p − x) and mass. LAMMPS-free; tests/unit/parmec_contact.
#pragma once

#include "obstacle.h"

#include <vector>

namespace dembridge::parmec_contact {

// A rigid body's state at the force evaluation: mass centre, rotation Λ (row-major, Parmec's stored
// matrix), linear velocity, spatial angular velocity, mass. kDoubles values in this order (one MPI message).
struct BodyPose {
  static constexpr int kDoubles = 19;
  Vec3 x{0, 0, 0};
  double lambda[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
  Vec3 v{0, 0, 0}, w{0, 0, 0};
  double mass = 0.0;
  void pack(double *out) const;
  static BodyPose unpack(const double *in);
};

class MeshBody {
 public:
  // triangles and colours as for an Obstacle (same validation, same errors), centre = the reference X.
  MeshBody(long tag, std::vector<mesh::TriangleNodes> triangles, std::vector<int> colors, const Vec3 &centre);

  long tag() const { return tag_; }
  const Obstacle &surface() const { return surface_; }  // triangles at the current pose, colours
  // The triangles in the reference configuration (never move): a rigid body's candidate search bins them once
  // and looks them up with the spheres taken to the reference frame (to_reference); the contacts themselves
  // are resolved on surface().
  const mesh::TriangleMesh &reference_mesh() const { return reference_.mesh(); }
  Vec3 to_reference(const Vec3 &p) const;  // X + Λᵀ (p − x)
  const BodyPose &pose() const { return pose_; }
  // Triangles to x + Λ(P − X) (kept as they are when x and Λ did not change).
  void place(const BodyPose &pose);
  // Material velocity of the body at p: v + ω × (p − x).
  Vec3 velocity_at(const Vec3 &p) const;

 private:
  long tag_;
  Obstacle surface_, reference_;
  Vec3 centre_;
  std::vector<mesh::TriangleNodes> arms_;  // P − X of every node
  std::vector<mesh::TriangleNodes> placed_;
  BodyPose pose_;
  bool placed_once_ = false;
};

}  // namespace dembridge::parmec_contact
