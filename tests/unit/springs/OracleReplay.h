// Runs a reference::LeapFrog model alongside an oracle history and measures the worst deviations.
#pragma once

#include <string>
#include <vector>

#include "Deviation.h"
#include "OracleData.h"
#include "ReferenceLeapFrog.h"

struct ReplayDeviations {
  Deviation displacement;  // x - x0 of every body, every sampled row
  Deviation velocity;      // v (and omega where sampled)
  Deviation force;         // spring F and SF
  Deviation stroke;        // spring STROKE
  Deviation friction;      // spring FF
  void print(const std::string& name) const;
};

// body_prefix[i]: column prefix of body i ("" for single-body histories, "p3_" ...); springs are "sprN_".
// Rows are aligned by step number n = round(TIME/h) (spec §1.3): positions after step n, v_{n+1},
// spring values of step n.
ReplayDeviations replay_against(reference::LeapFrog& model, const oracle::History& h, double step,
                                const std::vector<std::string>& body_prefix);
