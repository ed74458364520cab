// Parmec's BALL_JOINT (spec parmec-springs §9), LAMMPS-free: joints split into clusters (connected
// components of the joint graph, joints in Parmec's depth-first order); per cluster the velocity constraints
// U_rel(t_n) + U_rel(t_{n+1}) = 0 are assembled and solved for the joint impulses in Parmec's operation order
// (blocks as joints.cpp forms them, a skyline Crout LU as amgcl's skyline_lu factors them), so joint
// reactions agree with Parmec's to round-off. Bodies with zero inverse mass and inertia are kinematic
// (prescribed motion).
#pragma once

#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "body_rotation.h"


namespace dembridge::rigid {

struct JointDef {
  int body1 = 0, body2 = -1;  // body indices; body2 = -1: part1 pinned in space
  Vec3 arm1 = Vec3::Zero();   // body-frame arm b = Λ0ᵀ(P − X) of the joint point on each body
  Vec3 arm2 = Vec3::Zero();
};

struct BodyKinematics {
  double inv_mass = 0.0;                   // 0 for a kinematic body
  Mat3 inv_inertia = Mat3::Zero();         // referential J⁻¹ (0 for a kinematic body)
  Mat3 L = Mat3::Identity();               // Λ_{n+1/2}
  Vec3 v = Vec3::Zero(), W = Vec3::Zero();            // v_n, Ω_n
  Vec3 v_free = Vec3::Zero(), W_free = Vec3::Zero();  // end-of-step velocities without joint reactions,
  Vec3 kick = Vec3::Zero();  // ... v_free + kick: Parmec adds the force kick (h/m) f after the point velocity
};

class SingularCluster : public std::runtime_error {
 public:
  SingularCluster(const std::string &what, std::vector<int> joints) : std::runtime_error(what), joints(std::move(joints)) {}
  std::vector<int> joints;
};

class JointClusters {
 public:
  // throws std::invalid_argument for a body index out of range or a joint of a body with itself
  JointClusters(int nbodies, std::vector<JointDef> joints);
  ~JointClusters();
  const std::vector<std::vector<int>> &clusters() const { return clusters_; }
  const std::vector<JointDef> &joints() const { return joints_; }
  void set_arm(int joint, int end, const Vec3 &arm) { (end == 0 ? joints_[joint].arm1 : joints_[joint].arm2) = arm; }

  // Joint reactions R_i (force on body1 at the joint point; −R_i on body2) for step h.
  // q16: assemble the off-diagonal blocks transposed, as Parmec does. Throws SingularCluster.
  std::vector<Vec3> solve(const std::vector<BodyKinematics> &bodies, double h, bool q16) const;

  // Point velocity operator H = −Λ[b]× (U = v + H Ω).
  static Mat3 point_operator(const Mat3 &L, const Vec3 &arm);

 private:
  std::vector<JointDef> joints_;
  std::vector<std::vector<int>> clusters_;
  mutable std::vector<char> checked_;  // cluster rank verified (first solve)
};

}  // namespace dembridge::rigid
