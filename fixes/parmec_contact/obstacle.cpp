#include "obstacle.h"

#include <stdexcept>
#include <string>

namespace dembridge::parmec_contact {

namespace {

mesh::MeshOptions obstacle_options()
{
  mesh::MeshOptions o;
  o.curvature_tolerant = true;  // Parmec accepts any non-degenerate triangle (slivers included)
  return o;
}

}  // namespace

Vec3 closest_point_on_triangle(const Vec3 &a, const Vec3 &b, const Vec3 &c, const Vec3 &p)
{
  using mesh::add, mesh::dot, mesh::scale, mesh::sub;
  // Voronoi regions of the corners, then of the edges, else the face (barycentric coordinates)
  const Vec3 ab = sub(b, a), ac = sub(c, a), ap = sub(p, a);
  const double d1 = dot(ab, ap), d2 = dot(ac, ap);
  if (d1 <= 0.0 && d2 <= 0.0) return a;
  const Vec3 bp = sub(p, b);
  const double d3 = dot(ab, bp), d4 = dot(ac, bp);
  if (d3 >= 0.0 && d4 <= d3) return b;
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0) return add(a, scale(ab, d1 / (d1 - d3)));
  const Vec3 cp = sub(p, c);
  const double d5 = dot(ab, cp), d6 = dot(ac, cp);
  if (d6 >= 0.0 && d5 <= d6) return c;
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0) return add(a, scale(ac, d2 / (d2 - d6)));
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0)
    return add(b, scale(sub(c, b), (d4 - d3) / ((d4 - d3) + (d5 - d6))));
  const double denom = 1.0 / (va + vb + vc);
  return add(a, add(scale(ab, vb * denom), scale(ac, vc * denom)));
}

Obstacle::Obstacle(std::vector<mesh::TriangleNodes> triangles, std::vector<int> colors) :
    mesh_(std::move(triangles), obstacle_options()), colors_(std::move(colors))
{
  if (static_cast<int>(colors_.size()) != mesh_.size())
    throw std::invalid_argument("expected one colour per triangle (" + std::to_string(mesh_.size()) + "), got " +
                                std::to_string(colors_.size()));
  for (std::size_t t = 0; t < colors_.size(); ++t)
    if (colors_[t] <= 0)
      throw std::invalid_argument("colour of triangle " + std::to_string(t + 1) + " must be a positive integer, got " +
                                  std::to_string(colors_[t]));
}

void Obstacle::set_motion(const Vec3 &point, VelocityFn linear, VelocityFn angular)
{
  if (point_ >= 0) throw std::invalid_argument("the obstacle's motion is already defined");
  point_ = mesh_.attach_point(point);  // rotates and translates with the triangles
  linear_fn_ = std::move(linear);
  angular_fn_ = std::move(angular);
  moving_ = static_cast<bool>(linear_fn_) || static_cast<bool>(angular_fn_);
}

Vec3 Obstacle::velocity_at(const Vec3 &p) const
{
  if (!moving_) return {0.0, 0.0, 0.0};
  return mesh::add(v_, mesh::cross(w_, mesh::sub(p, point())));
}

void Obstacle::read_velocity(double t)
{
  v_ = linear_fn_ ? linear_fn_(t) : Vec3{0.0, 0.0, 0.0};
  w_ = angular_fn_ ? angular_fn_(t) : Vec3{0.0, 0.0, 0.0};
}

void Obstacle::move(double h)
{
  const double wlen = mesh::norm(w_);
  if (wlen > 0.0) mesh_.rotate(h * wlen, mesh::scale(w_, 1.0 / wlen), point());
  const Vec3 dx = mesh::scale(v_, h);
  if (dx[0] != 0.0 || dx[1] != 0.0 || dx[2] != 0.0) mesh_.translate(dx);
}

void Obstacle::start(double t0, double h, bool parmec_start)
{
  if (!moving_) return;
  if (parmec_start) {
    read_velocity(t0 + 0.5 * h);
    move(h);
  } else {
    read_velocity(t0);
    move(0.5 * h);
  }
}

void Obstacle::advance(double t, double h)
{
  if (!moving_) return;
  read_velocity(t + h);
  move(h);
}

std::vector<double> Obstacle::save() const
{
  std::vector<double> out = mesh_.save_state();
  out.insert(out.end(), v_.begin(), v_.end());
  out.insert(out.end(), w_.begin(), w_.end());
  return out;
}

void Obstacle::restore(const std::vector<double> &buf)
{
  if (buf.size() < 6) throw std::invalid_argument("obstacle restart data too short");
  mesh_.restore_state(std::vector<double>(buf.begin(), buf.end() - 6));
  for (int k = 0; k < 3; ++k) {
    v_[k] = buf[buf.size() - 6 + k];
    w_[k] = buf[buf.size() - 3 + k];
  }
}

}  // namespace dembridge::parmec_contact
