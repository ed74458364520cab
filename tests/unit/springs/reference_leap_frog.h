// A small LAMMPS-free rigid-body model that drives the spring kernels with Parmec's staggered leap-frog
// (spec parmec-springs §1.1-§1.2), written from the spec for the oracle comparisons. Quirks Q1 (first
// force evaluation sees omega h/2) and Q3 (expmap Omega2*Omega3 typo) can be switched on to reproduce
// the upstream oracle builds; the fixedQ1Q3 oracle is matched with both off.
#pragma once

#include <Eigen/Dense>
#include <vector>

#include "equivalent_mass.h"
#include "spring_geometry.h"
#include "spring_law.h"
#include "spring_state.h"
#include "spring_step.h"

namespace reference {

using dembridge::springs::Vec3;
using Mat3 = Eigen::Matrix3d;
using V3 = Eigen::Vector3d;

struct Body {
  double mass = 1.0;
  Mat3 J = Mat3::Identity();  // referential inertia
  V3 X = V3::Zero();          // reference centre
  V3 x = V3::Zero();          // centre (half-step positions during the run)
  Mat3 L = Mat3::Identity();  // rotation Λ
  V3 v = V3::Zero();          // velocity
  V3 W = V3::Zero();          // body angular velocity Ω
  V3 w = V3::Zero();          // spatial angular velocity ω
  V3 f = V3::Zero(), t = V3::Zero();  // force and spatial torque of the last step
  std::vector<V3> restrain_linear, restrain_angular;  // orthonormal restrained directions
  dembridge::springs::BodyMass mass_properties() const;
};

struct Spring {
  int part1 = 0, part2 = -1;
  V3 P1 = V3::Zero(), P2 = V3::Zero();  // reference points (Plane: P2 = projected anchor)
  dembridge::springs::DirectionMode mode = dembridge::springs::DirectionMode::Follower;
  Vec3 d{};     // Constant/Planar direction, Plane reference normal
  double stroke0 = 0.0;
  dembridge::springs::SpringLaw law;
  dembridge::springs::SpringState state;
  dembridge::springs::SpringForce last;  // outputs of the last step
};

struct Options {
  double h = 1e-3;
  V3 gravity = V3::Zero();
  bool q1 = false, q3 = false;
  dembridge::springs::EqmArm eqm_arm = dembridge::springs::EqmArm::Correct;
};

class LeapFrog {
 public:
  LeapFrog(std::vector<Body> bodies, std::vector<Spring> springs, Options opt);
  // One step n: springs at x_{n+1/2}, v_n, then kick and drift. Advances time by h.
  void step();
  double time() const { return time_; }
  long steps() const { return steps_; }
  const std::vector<Body>& bodies() const { return bodies_; }
  const std::vector<Spring>& springs() const { return springs_; }
  // Adds a spring with stroke0 computed from its reference points.
  static Spring make_spring(int part1, const V3& P1, int part2, const V3& P2, dembridge::springs::DirectionMode mode,
                            const Vec3& d, const dembridge::springs::SpringLaw& law);

 private:
  void start();
  std::vector<Body> bodies_;
  std::vector<Spring> springs_;
  Options opt_;
  double time_ = 0.0;
  long steps_ = 0;
};

Mat3 expmap(const V3& theta, bool q3);
Vec3 to_vec(const V3& v);
V3 to_v3(const Vec3& v);

}  // namespace reference
