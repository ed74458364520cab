#include "mesh_movers.h"

#include <cmath>

namespace dembridge::mesh {

namespace {

constexpr double kTwoPi = 2. * 3.14159265358979323846;

void add_translation_velocity(TriangleMesh &m, const Vec3 &v)
{
  if (!m.has_velocity()) m.zero_velocity();
  for (int t = 0; t < m.size(); ++t)
    for (int k = 0; k < 3; ++k) m.add_node_velocity(t, k, v);
}

// node velocity += (axis * rate) x (node - origin), from the already rotated nodes
void add_rotation_velocity(TriangleMesh &m, const Vec3 &axis, double rate, const Vec3 &origin)
{
  if (!m.has_velocity()) m.zero_velocity();
  const Vec3 w = scale(axis, rate);
  for (int t = 0; t < m.size(); ++t)
    for (int k = 0; k < 3; ++k) m.add_node_velocity(t, k, cross(w, sub(m.node(t, k), origin)));
}

}  // namespace

Vec3 unit_axis(const Vec3 &a) { return div_by(a, norm(a)); }

void LinearMover::step(TriangleMesh &m, double, double dt)
{
  m.translate(scale(v_, dt));
  add_translation_velocity(m, v_);
}

WiggleMover::WiggleMover(const Vec3 &amplitude, double period) : amp_(amplitude), omega_(kTwoPi / period) {}

void WiggleMover::step(TriangleMesh &m, double time, double dt)
{
  const Vec3 v = scale(amp_, omega_ * std::cos(omega_ * time));
  m.translate(scale(v, dt));
  add_translation_velocity(m, v);
}

RotateMover::RotateMover(TriangleMesh &m, const Vec3 &origin, const Vec3 &axis, double omega)
    : origin_(m.attach_point(origin)), axis_(unit_axis(axis)), omega_(omega)
{
}

void RotateMover::step(TriangleMesh &m, double, double dt)
{
  const Vec3 p = m.attached_point(origin_);
  m.rotate(omega_ * dt, axis_, p);
  add_rotation_velocity(m, axis_, omega_, p);
}

RiggleMover::RiggleMover(const Vec3 &origin, const Vec3 &axis, double period, double amplitude_deg)
    : origin_(origin), axis_(unit_axis(axis)), omega_(kTwoPi / period),
      amp_(3.14159265358979323846 * amplitude_deg / 180.)
{
}

void RiggleMover::step(TriangleMesh &m, double time, double dt)
{
  const double rate = omega_ * amp_ * std::cos(omega_ * time);
  m.rotate(rate * dt, axis_, origin_);
  add_rotation_velocity(m, axis_, rate, origin_);
}

double Harmonics::rate(double time) const
{
  double r = 0.0;
  for (std::size_t j = 0; j < amplitude.size(); ++j) r = r - amplitude[j] * omega[j] * std::sin(omega[j] * time + phase[j]);
  return r;
}

ViblinMover::ViblinMover(const Vec3 &axis, Harmonics h) : axis_(unit_axis(axis)), h_(std::move(h)) {}

void ViblinMover::step(TriangleMesh &m, double time, double dt)
{
  const Vec3 v = scale(axis_, h_.rate(time));
  m.translate(scale(v, dt));
  add_translation_velocity(m, v);
}

VibrotMover::VibrotMover(const Vec3 &origin, const Vec3 &axis, Harmonics h)
    : origin_(origin), axis_(unit_axis(axis)), h_(std::move(h))
{
}

void VibrotMover::step(TriangleMesh &m, double time, double dt)
{
  const double rate = h_.rate(time);
  m.rotate(rate * dt, axis_, origin_);
  add_rotation_velocity(m, axis_, rate, origin_);
}

}  // namespace dembridge::mesh
