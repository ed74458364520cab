#include "stream_insertion.h"

#include <algorithm>
#include <cmath>

namespace dembridge::insertion {

StreamFace::StreamFace(std::vector<Triangle> triangles, const std::vector<double> &areas,
                       std::vector<unsigned> boundary_edges) :
    tri_(std::move(triangles)), border_(std::move(boundary_edges))
{
  double acc = 0.0;
  for (double a : areas) {
    acc += a;
    area_acc_.push_back(acc);
    area_total_ += a;
  }
}

int StreamFace::draw(ParkMiller &rng, double *pos) const
{
  // the first triangle whose accumulated area reaches r (LIGGGHTS's searchElementByAreaAcc)
  const double r = rng.uniform() * area_total_;
  int t = static_cast<int>(std::lower_bound(area_acc_.begin(), area_acc_.end(), r) - area_acc_.begin());
  t = std::min(t, size() - 1);
  double u, v;
  do {
    u = rng.uniform();
    v = rng.uniform();
  } while (u + v > 1);
  const double b0 = 1. - u - v, b1 = v, b2 = u;
  const Triangle &n = tri_[t];
  for (int k = 0; k < 3; ++k) pos[k] = b0 * n[0][k] + b1 * n[1][k] + b2 * n[2][k];
  return t;
}

double distance_to_segment(const double *p, const double *a, const double *b)
{
  double ab[3], ap[3], l2 = 0.0, t = 0.0;
  for (int k = 0; k < 3; ++k) {
    ab[k] = b[k] - a[k];
    ap[k] = p[k] - a[k];
    l2 += ab[k] * ab[k];
    t += ab[k] * ap[k];
  }
  t = l2 > 0. ? std::clamp(t / l2, 0., 1.) : 0.;
  double d2 = 0.0;
  for (int k = 0; k < 3; ++k) d2 += (ap[k] - t * ab[k]) * (ap[k] - t * ab[k]);
  return std::sqrt(d2);
}

bool StreamFace::draw_within(ParkMiller &rng, double delta, double *pos) const
{
  for (int ntry = 0; ntry < kMaxTryWithin; ++ntry) {
    draw(rng, pos);
    bool far = true;
    for (int t = 0; t < size() && far; ++t)
      for (int k = 0; k < 3 && far; ++k)
        if ((border_[t] >> k) & 1u) far = distance_to_segment(pos, tri_[t][k].data(), tri_[t][(k + 1) % 3].data()) >= delta;
    if (far) return true;
  }
  return false;
}

bool in_box(const Box &box, const double *x)
{
  for (int k = 0; k < 3; ++k)
    if (x[k] < box.lo[k] || x[k] >= box.hi[k]) return false;
  return true;
}

namespace {
// pos += n * depth, the arithmetic of LIGGGHTS (ext = n * r, then pos + ext)
void push_back_by(double *pos, const double *n, double depth)
{
  for (int k = 0; k < 3; ++k) pos[k] = pos[k] + n[k] * depth;
}

// LIGGGHTS's generate_random of insert/stream: face point, then depth -(U*L + r), or -(U*(L-2r) + r)
// without overlapcheck.
void candidate(const StreamFace &face, const StreamSettings &s, double rad, ParkMiller &face_rng,
               ParkMiller &insert_rng, double *pos, bool &bad_within)
{
  if (s.all_in) {
    if (!face.draw_within(face_rng, rad, pos)) bad_within = true;
  } else {
    face.draw(face_rng, pos);
  }
  const double span = s.overlapcheck ? s.extrude_max : s.extrude_max - 2. * rad;
  const double depth = -1. * (insert_rng.uniform() * span + rad + s.extrude_min);
  push_back_by(pos, s.normal, depth);
}
}  // namespace

void narrow_to_box(StreamSettings &s, const double *p_ref)
{
  const double L = s.extrude_length;
  double lo = L, hi = 0.0;
  for (int c = 0; c < 8; ++c) {
    const double corner[3] = {(c & 1) ? s.box.hi[0] : s.box.lo[0], (c & 2) ? s.box.hi[1] : s.box.lo[1],
                              (c & 4) ? s.box.hi[2] : s.box.lo[2]};
    double dot = 0.0;
    for (int k = 0; k < 3; ++k) dot += (corner[k] - p_ref[k]) * s.normal[k];
    dot = -dot;
    if (dot > 0. && dot < L) {
      hi = std::max(hi, dot);
      lo = std::min(lo, dot);
    } else if (dot < 0.) {
      lo = 0.;
    } else if (dot >= L) {
      hi = L;
    }
  }
  s.extrude_min = lo == L ? 0. : lo;
  s.extrude_max = hi == 0. ? L : hi;
}

double fraction_in_box(const StreamFace &face, const StreamSettings &s, int ntry, ParkMiller &face_rng,
                       ParkMiller &insert_rng)
{
  int inside = 0;
  double pos[3];
  for (int i = 0; i < ntry; ++i) {
    face.draw(face_rng, pos);
    push_back_by(pos, s.normal, -1. * (insert_rng.uniform() * s.extrude_length));
    if (in_box(s.box, pos)) ++inside;
  }
  return static_cast<double>(inside) / static_cast<double>(ntry);
}

std::vector<StreamPlaced> place_stream(const std::vector<int> &list, const std::vector<double> &radii,
                                       const StreamFace &face, const StreamSettings &s, int maxtry,
                                       ParkMiller &face_rng, ParkMiller &insert_rng, OverlapGrid &grid,
                                       bool &bad_within)
{
  std::vector<StreamPlaced> placed;
  const int n = static_cast<int>(list.size());
  int ntry = 0;
  StreamPlaced p;
  auto try_position = [&](double r) {  // draws until inside the box and r from its faces, or out of tries
    do {
      candidate(face, s, r, face_rng, insert_rng, p.x, bad_within);
      ++ntry;
    } while (ntry < maxtry && (!in_box(s.box, p.x) || distance_to_box_faces(s.box, p.x) < r));
    return ntry < maxtry;
  };
  if (!s.overlapcheck) {
    for (int k = 0; k < n; ++k) {
      // LIGGGHTS takes the template of the next insertion, not of the k-th try
      const int t = list[placed.size()];
      if (try_position(radii[t])) {
        p.template_index = t;
        placed.push_back(p);
      }
    }
    return placed;
  }
  while (ntry < maxtry && static_cast<int>(placed.size()) < n) {
    const int t = list[placed.size()];
    const double r = radii[t];
    bool ok = false;
    while (!ok && ntry < maxtry)
      if (try_position(r)) ok = !grid.overlaps(p.x, r);
    if (ok) {
      grid.add(p.x, r);
      p.template_index = t;
      placed.push_back(p);
    }
  }
  return placed;
}

}  // namespace dembridge::insertion
