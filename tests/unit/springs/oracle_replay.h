// Runs a reference::LeapFrog model alongside an oracle history and measures the worst deviations.
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "deviation.h"
#include "oracle_data.h"
#include "reference_leap_frog.h"

struct ReplayDeviations {
  Deviation displacement;  // x - x0 of every body, every sampled row
  Deviation velocity;      // v (and omega where sampled)
  Deviation force;         // spring F and SF
  Deviation stroke;        // spring STROKE
  Deviation friction;      // spring FF
  long rows = 0;           // history rows compared
  void print(const std::string& name) const;
};

// The history rows compared: sample k = round(TIME / interval) is compared when k < first, k % every == 0
// or TIME lies in one of `windows` (closed time intervals around events, every row there).
// The oracle's long histories are kept in tests/data thinned by the same rule (thin_histories.py), so the
// full recording and the thinned copy give the same comparison; `expected_rows` (rows 1..last) lets a test
// check that none is missing.
struct RowSample {
  double interval = 0.0;  // the oracle's history interval; 0: compare every row
  long first = 0, every = 1;
  std::vector<std::pair<double, double>> windows;
  bool compared(double time) const;
  long expected_rows(double last_time) const;
};

// body_prefix[i]: column prefix of body i ("" for single-body histories, "p3_" ...); springs are "sprN_".
// Rows are aligned by step number n = round(TIME/h) (spec §1.3): positions after step n, v_{n+1},
// spring values of step n. The model runs every step; only the sampled rows are compared.
ReplayDeviations replay_against(reference::LeapFrog& model, const oracle::History& h, double step,
                                const std::vector<std::string>& body_prefix, const RowSample& sample = {});
