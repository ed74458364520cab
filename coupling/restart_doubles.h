// The restart records of fix mbdyn and fix mbdyn ... modal: a list of doubles written and read in
// the same order (every integer stored is far below 2^53). Reading past the end or a bad length
// clears ok() instead of reading garbage; the caller refuses the record then.
#pragma once

#include <cmath>
#include <cstddef>
#include <string>
#include <vector>

namespace dembridge {

class RestartDoubles {
 public:
  explicit RestartDoubles(std::vector<double> &out) : out_(&out) {}
  RestartDoubles(const double *in, std::size_t n) : in_(in), n_(n) {}

  void put(double v) { out_->push_back(v); }
  void put(const double *v, std::size_t n) { out_->insert(out_->end(), v, v + n); }
  void put_vector(const std::vector<double> &v)
  {
    put(static_cast<double>(v.size()));
    put(v.data(), v.size());
  }
  void put_text(const std::string &s)
  {
    put(static_cast<double>(s.size()));
    for (unsigned char c : s) put(c);
  }

  bool ok() const { return ok_; }
  double get()
  {
    if (pos_ >= n_) {
      ok_ = false;
      return 0.0;
    }
    return in_[pos_++];
  }
  long long get_int() { return std::llround(get()); }
  void get(double *v, std::size_t n)
  {
    for (std::size_t i = 0; i < n; ++i) v[i] = get();
  }
  void get_vector(std::vector<double> &v)
  {
    const long long n = get_int();
    if (n < 0 || static_cast<std::size_t>(n) > n_ - pos_) {
      ok_ = false;
      return;
    }
    v.resize(static_cast<std::size_t>(n));
    get(v.data(), v.size());
  }
  std::string get_text()
  {
    const long long n = get_int();
    std::string s;
    if (n < 0 || static_cast<std::size_t>(n) > n_ - pos_) {
      ok_ = false;
      return s;
    }
    for (long long i = 0; i < n; ++i) s.push_back(static_cast<char>(get_int()));
    return s;
  }

 private:
  std::vector<double> *out_ = nullptr;
  const double *in_ = nullptr;
  std::size_t n_ = 0, pos_ = 0;
  bool ok_ = true;
};

}  // namespace dembridge
