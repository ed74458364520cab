// The global restart record of an insertion fix: a list of doubles headed by the record's kind (which
// fix wrote it, which layout) and its length, so a restart file written by another fix or layout is
// refused instead of read as garbage. LAMMPS-free.
#pragma once

#include "park_miller.h"

#include <cstdio>
#include <vector>

namespace dembridge::insertion {

class RestartWriter {
 public:
  explicit RestartWriter(double kind) : v_{kind, 0.0} {}
  void put(double x) { v_.push_back(x); }
  void put(const ParkMiller &rng);
  // Writes [bytes][doubles] as LAMMPS's Fix::write_restart expects (call on rank 0 only).
  void write(FILE *fp);

 private:
  std::vector<double> v_;
};

class RestartReader {
 public:
  // Throws std::invalid_argument unless buf holds a record of this kind.
  RestartReader(const char *buf, double kind);
  double get();  // throws std::invalid_argument past the end
  long get_long() { return static_cast<long>(get()); }
  bool get_bool() { return get() != 0.0; }
  void get(ParkMiller &rng);

 private:
  std::vector<double> v_;
  std::size_t next_ = 2;
};

}  // namespace dembridge::insertion
