// Parmec's OBSTACLE (seed: OBSTACLE(triangles, color | point, linear, angular)): a triangle set on the wall
// mesh machinery (walls/mesh: validation, topology, sphere-triangle distance, binning), coloured per
// triangle, static or moving rigidly with a linear velocity of its reference point and a spatial angular
// velocity, both functions of time. LAMMPS-free; tests/unit/parmec_contact.
#pragma once

#include "triangle_mesh.h"

#include <functional>
#include <vector>

namespace dembridge::parmec_contact {

using mesh::Vec3;
using VelocityFn = std::function<Vec3(double)>;

// The point of triangle (a, b, c) closest to p (plain geometry, every edge and corner active): Parmec's
// per-triangle contact point, used by 'quirks parmec'.
Vec3 closest_point_on_triangle(const Vec3 &a, const Vec3 &b, const Vec3 &c, const Vec3 &p);

class Obstacle {
 public:
  // colors: one per triangle (each > 0). Throws mesh::MeshError for a bad triangle (1-based index) and
  // std::invalid_argument for bad colours.
  Obstacle(std::vector<mesh::TriangleNodes> triangles, std::vector<int> colors);

  // A moving obstacle: reference point and velocity histories (null = zero). Once, before start().
  void set_motion(const Vec3 &point, VelocityFn linear, VelocityFn angular);
  bool moving() const { return moving_; }

  const mesh::TriangleMesh &mesh() const { return mesh_; }
  int color(int t) const { return colors_[t]; }
  const Vec3 &point() const { return mesh_.attached_point(point_); }
  const Vec3 &linear() const { return v_; }
  const Vec3 &angular() const { return w_; }

  // Velocity of the obstacle's material point at p: v + w x (p - point).
  Vec3 velocity_at(const Vec3 &p) const;

  // Before the first step at time t0 (step h): the obstacle goes to its position at the particles' half step.
  // Corrected: a half step h/2 with v(t0). parmec_start: Parmec's full step h with v(t0 + h/2) (obstacles
  // then lead the particles by h/2). The current velocity is the one of that move.
  void start(double t0, double h, bool parmec_start);
  // After the forces of the step at time t: velocities read at t + h, rotation by h w about the point,
  // then translation by h v (Parmec obstacles.ispc order).
  void advance(double t, double h);

  // The triangles at a pose computed by the caller (a MESH body's x + Λ(P − X); mesh_body.h).
  void place(const std::vector<mesh::TriangleNodes> &nodes) { mesh_.place_nodes(nodes); }

  // Restart: mesh state (incl. the point) and the current velocities.
  std::vector<double> save() const;
  void restore(const std::vector<double> &buf);

 private:
  mesh::TriangleMesh mesh_;
  std::vector<int> colors_;
  int point_ = -1;
  bool moving_ = false;
  VelocityFn linear_fn_, angular_fn_;
  Vec3 v_{0, 0, 0}, w_{0, 0, 0};
  void read_velocity(double t);
  void move(double h);
};

}  // namespace dembridge::parmec_contact
