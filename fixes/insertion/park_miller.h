// The Park-Miller "minimal standard" generator with Schrage's factorisation and Marsaglia's polar
// Gaussian, as LIGGGHTS 3.8 draws its insertion streams (doc/fix_insert_pack.md, "Random streams").
// LAMMPS-free; one object per stream.
#pragma once

#include <array>

namespace dembridge::insertion {

class ParkMiller {
 public:
  explicit ParkMiller(int seed = 1) : seed_(seed) {}
  void reset(int seed)
  {
    seed_ = seed;
    have_second_ = false;
  }
  int state() const { return seed_; }
  double uniform()
  {
    const int k = seed_ / kQ;
    seed_ = kA * (seed_ - k * kQ) - kR * k;
    if (seed_ < 0) seed_ += kM;
    return (1.0 / kM) * seed_;
  }
  double gaussian();  // caches the second value of each polar pair
  // The whole state (seed, cached second Gaussian and its flag), for restart files; restore() throws
  // std::invalid_argument on a state no stream can reach.
  std::array<double, 3> saved() const { return {double(seed_), have_second_ ? 1.0 : 0.0, second_}; }
  void restore(const std::array<double, 3> &s);
  void skip(long n)
  {
    for (long i = 0; i < n; ++i) uniform();
  }

 private:
  static constexpr int kA = 16807, kM = 2147483647, kQ = 127773, kR = 2836;
  int seed_;
  bool have_second_ = false;
  double second_ = 0.0;
};

}  // namespace dembridge::insertion
