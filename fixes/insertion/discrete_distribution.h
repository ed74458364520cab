// fix particledistribution/discrete's arithmetic (LIGGGHTS 3.8): weights normalised (and turned from
// mass to number fractions unless number-based), templates ordered large to small, and the
// per-insertion list of templates with its stochastic rounding. LAMMPS-free.
#pragma once

#include "park_miller.h"

#include <vector>

namespace dembridge::insertion {

// A particletemplate/sphere: constant radius and density, as LIGGGHTS 3.8 accepts.
struct SphereTemplate {
  int type = 1;
  double radius = 0.0;
  double density = 0.0;
  // The same expressions (and operation order) as LIGGGHTS, so the masses are bit-identical.
  double volume() const { return radius * radius * radius * 4. * 3.14159265358979323846 / 3.; }
  double mass() const { return density * volume(); }
};

class DiscreteDistribution {
 public:
  // weights >= 0 with a positive sum (checked by the caller); mass_based: weights are mass fractions.
  DiscreteDistribution(std::vector<SphereTemplate> templates, std::vector<double> weights, bool mass_based);

  // true if the weights given did not sum to 1 (LIGGGHTS warns and normalises)
  bool normalised() const { return normalised_; }
  const std::vector<SphereTemplate> &templates() const { return templates_; }
  const std::vector<double> &number_fractions() const { return number_fraction_; }
  double vol_expect() const { return vol_expect_; }
  double mass_expect() const { return mass_expect_; }
  double max_radius() const;
  // Template indices from the largest to the smallest volume (a stable bubble sort, as LIGGGHTS).
  const std::vector<int> &order() const { return order_; }

  // The templates of n particles in insertion order (large to small). exact: the counts are
  // truncated and the missing ones given out by remainder (random_distribute exact, the default);
  // otherwise int(n*w + U) per template (random_distribute uncorrelated).
  std::vector<int> draw_list(int n, bool exact, ParkMiller &rng) const;

 private:
  std::vector<SphereTemplate> templates_;
  std::vector<double> number_fraction_;
  std::vector<int> order_;
  bool normalised_ = false;
  double vol_expect_ = 0.0, mass_expect_ = 0.0;
};

}  // namespace dembridge::insertion
