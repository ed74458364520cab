// One insertion event of fix insert/stream (LIGGGHTS 3.8): points on the insertion face drawn on the
// face's own stream (triangle by accumulated area, then barycentric (u,v) by rejection), pushed back
// into the extrusion volume by a depth drawn on the insert fix's stream, tried against the box and
// the overlap grid in the order of LIGGGHTS's x_v_omega. LAMMPS-free.
#pragma once

#include "overlap_grid.h"
#include "park_miller.h"
#include "region_sampling.h"

#include <array>
#include <vector>

namespace dembridge::insertion {

using Triangle = std::array<std::array<double, 3>, 3>;

class StreamFace {
 public:
  // areas: LIGGGHTS's triangle areas, in triangle order (they decide which triangle a draw picks).
  // boundary_edges: per triangle, bit k set if edge k (node k to node k+1) lies on the face's border.
  StreamFace(std::vector<Triangle> triangles, const std::vector<double> &areas, std::vector<unsigned> boundary_edges);
  int size() const { return static_cast<int>(tri_.size()); }
  // A point on the face: 1 uniform picks the triangle, then (u,v) pairs until u + v <= 1.
  int draw(ParkMiller &rng, double *pos) const;
  // all_in: redrawn (at most kMaxTryWithin times) while closer than delta to a border edge;
  // false if every try was too close (LIGGGHTS warns "'All_in yes' did not succeed").
  bool draw_within(ParkMiller &rng, double delta, double *pos) const;
  static constexpr int kMaxTryWithin = 10000;

 private:
  std::vector<Triangle> tri_;
  std::vector<double> area_acc_;
  double area_total_ = 0.0;
  std::vector<unsigned> border_;
};

// Distance from p to the segment a-b.
double distance_to_segment(const double *p, const double *a, const double *b);

struct StreamSettings {
  double normal[3];          // unit face normal, oriented along the insertion velocity
  double extrude_length;     // L
  // the depths a particle is drawn from: [min, min + max] behind the face (LIGGGHTS's extrude_length_min/max;
  // 0 and L unless 'parallel yes' narrows them to the box, narrow_to_box)
  double extrude_min = 0.0, extrude_max = 0.0;
  bool overlapcheck = true;
  bool all_in = false;
  Box box;                   // the simulation box (LIGGGHTS: the rank's sub-domain)
};

// LIGGGHTS's calc_ins_fraction with 'parallel yes' (on one rank, the sub-domain = the box): the depths
// behind the face (at p_ref) of the box corners between 0 and L bound the drawn depths.
void narrow_to_box(StreamSettings &s, const double *p_ref);

// LIGGGHTS's Domain::is_in_subdomain for a box: lo <= x < hi in each direction.
bool in_box(const Box &box, const double *x);

// The share of the extrusion volume inside the box: ntry points on the face pushed back by U*L
// (1 draw of the face stream's kind plus 1 uniform of the insert stream per point).
double fraction_in_box(const StreamFace &face, const StreamSettings &s, int ntry, ParkMiller &face_rng,
                       ParkMiller &insert_rng);

struct StreamPlaced {
  double x[3];
  int template_index;
};

// Places list[0..] in order within n * maxattempt tries (LIGGGHTS's x_v_omega of insert/stream).
// Without overlapcheck a particle whose tries ran out is skipped and the next one still tried (each
// with one more draw); with it, the placed ones are a prefix of the list. bad_within: set when an
// all_in draw gave up.
std::vector<StreamPlaced> place_stream(const std::vector<int> &list, const std::vector<double> &radii,
                                       const StreamFace &face, const StreamSettings &s, int maxtry,
                                       ParkMiller &face_rng, ParkMiller &insert_rng, OverlapGrid &grid,
                                       bool &bad_within);

}  // namespace dembridge::insertion
