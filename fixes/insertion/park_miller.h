// The Park-Miller "minimal standard" generator with Schrage's factorisation and Marsaglia's polar
// Gaussian, as LIGGGHTS 3.8 draws its insertion streams (doc/fix_insert_pack.md, "Random streams").
// LAMMPS-free; one object per stream.
#pragma once

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
