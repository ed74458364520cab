#include "discrete_distribution.h"

#include <cmath>

namespace dembridge::insertion {

DiscreteDistribution::DiscreteDistribution(std::vector<SphereTemplate> templates, std::vector<double> weights,
                                           bool mass_based) :
    templates_(std::move(templates)), number_fraction_(std::move(weights))
{
  const int n = static_cast<int>(templates_.size());
  double sum = 0.0;
  for (double w : number_fraction_) sum += w;
  normalised_ = std::fabs(sum - 1.) > 0.00001;
  for (double &w : number_fraction_) w /= sum;
  if (mass_based) {
    for (int i = 0; i < n; ++i) number_fraction_[i] = number_fraction_[i] / templates_[i].mass();
    sum = 0.0;
    for (double w : number_fraction_) sum += w;
    for (double &w : number_fraction_) w /= sum;
  }
  for (int i = 0; i < n; ++i) {
    vol_expect_ += templates_[i].volume() * number_fraction_[i];
    mass_expect_ += templates_[i].mass() * number_fraction_[i];
  }
  order_.resize(n);
  for (int i = 0; i < n; ++i) order_[i] = i;
  bool swapped;
  int passes = n;
  do {
    swapped = false;
    for (int i = 0; i < n - 1; ++i)
      if (templates_[order_[i]].volume() < templates_[order_[i + 1]].volume()) {
        std::swap(order_[i], order_[i + 1]);
        swapped = true;
      }
    --passes;
  } while (swapped && passes > 0);
}

double DiscreteDistribution::max_radius() const
{
  double r = 0.0;
  for (const auto &t : templates_) r = std::max(r, t.radius);
  return r;
}

std::vector<int> DiscreteDistribution::draw_list(int n, bool exact, ParkMiller &rng) const
{
  const int nt = static_cast<int>(templates_.size());
  std::vector<int> count(nt, 0);
  if (!exact) {
    for (int i = 0; i < nt; ++i) count[i] = static_cast<int>(static_cast<double>(n) * number_fraction_[i] + rng.uniform());
  } else {
    std::vector<double> remainder(nt);
    int truncated = 0;
    for (int i = 0; i < nt; ++i) {
      count[i] = static_cast<int>(static_cast<double>(n) * number_fraction_[i]);
      truncated += count[i];
      remainder[i] = static_cast<double>(n) * number_fraction_[i] - static_cast<double>(count[i]);
    }
    const int gap = n - truncated;
    for (int g = 0; g < gap; ++g) {
      const double r = rng.uniform() * static_cast<double>(gap);
      int j = 0;
      double rsum = remainder[0];
      while (rsum < r && j < nt - 1) rsum += remainder[++j];
      count[j]++;
    }
  }
  std::vector<int> list;
  for (int i = 0; i < nt; ++i) list.insert(list.end(), count[order_[i]], order_[i]);
  return list;
}

}  // namespace dembridge::insertion
