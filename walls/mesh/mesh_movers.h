// The fix move/mesh motions (spec liggghts-walls §7.2), each an incremental update of the mesh
// plus its contribution to the node velocities. Several movers stack on one mesh: the first one
// of the step zeroes the velocities (the caller does that), then each adds its own motion.
// `time` is the mover's total time after this step's increment, `dt` the step.
#pragma once

#include "triangle_mesh.h"

#include <memory>
#include <vector>

namespace dembridge::mesh {

class MeshMover {
 public:
  virtual ~MeshMover() = default;
  virtual void step(TriangleMesh &m, double time, double dt) = 0;
};

// linear vx vy vz  (linear/variable: the caller sets the velocity before every step)
class LinearMover : public MeshMover {
 public:
  explicit LinearMover(const Vec3 &v) : v_(v) {}
  void set_velocity(const Vec3 &v) { v_ = v; }
  void step(TriangleMesh &m, double time, double dt) override;

 private:
  Vec3 v_;
};

// wiggle amplitude ax ay az period T: v = A w cos(w t), displacement v dt
class WiggleMover : public MeshMover {
 public:
  WiggleMover(const Vec3 &amplitude, double period);
  void step(TriangleMesh &m, double time, double dt) override;

 private:
  Vec3 amp_;
  double omega_;
};

// rotate origin P axis a period T (rotate/variable: omega set before every step). The origin is
// a point attached to the mesh, so it follows movers stacked before this one.
class RotateMover : public MeshMover {
 public:
  RotateMover(TriangleMesh &m, const Vec3 &origin, const Vec3 &axis, double omega);
  void set_omega(double omega) { omega_ = omega; }
  void step(TriangleMesh &m, double time, double dt) override;

 private:
  int origin_;
  Vec3 axis_;
  double omega_;
};

// riggle origin P axis a period T amplitude deg: angular rate A w cos(w t) about a fixed P
class RiggleMover : public MeshMover {
 public:
  RiggleMover(const Vec3 &origin, const Vec3 &axis, double period, double amplitude_deg);
  void step(TriangleMesh &m, double time, double dt) override;

 private:
  Vec3 origin_, axis_;
  double omega_, amp_;
};

// viblin / vibrot: x(t) = sum_j A_j cos(w_j t + phi_j) along the axis (or as an angle about it)
struct Harmonics {
  std::vector<double> amplitude, phase, omega;  // omega_j = 2 pi / period_j
  double rate(double time) const;               // d/dt of the sum at time
};

class ViblinMover : public MeshMover {
 public:
  ViblinMover(const Vec3 &axis, Harmonics h);
  void step(TriangleMesh &m, double time, double dt) override;

 private:
  Vec3 axis_;
  Harmonics h_;
};

class VibrotMover : public MeshMover {
 public:
  VibrotMover(const Vec3 &origin, const Vec3 &axis, Harmonics h);
  void step(TriangleMesh &m, double time, double dt) override;

 private:
  Vec3 origin_, axis_;
  Harmonics h_;
};

// LIGGGHTS normalises mover axes as a * (1/|a|); a zero axis is the caller's error to report.
Vec3 unit_axis(const Vec3 &a);

}  // namespace dembridge::mesh
