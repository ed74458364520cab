// The global restart record of an insertion fix: a list of doubles headed by the record's kind (which
// fix wrote it, which layout) and its length, so a restart file written by another fix or layout is
// refused instead of read as garbage. LAMMPS-free.
#pragma once

#include "park_miller.h"

#include <cstdint>
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

// What every insertion fix writes first: its seed (checked on reading) and how far it has got.
struct InsertionProgress {
  int seed = 0;
  std::int64_t next_step = 0;    // next insertion step, 0 when done
  std::int64_t most_recent = -1; // last insertion step
  long ninserted = 0;
  double mass_inserted = 0.0;
  bool exact_number = false;
};

void put(RestartWriter &w, const InsertionProgress &p);
// Throws std::invalid_argument naming both seeds unless the record was written with expected_seed.
InsertionProgress get_progress(RestartReader &r, int expected_seed);

}  // namespace dembridge::insertion
