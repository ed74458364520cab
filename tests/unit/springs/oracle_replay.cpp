#include "oracle_replay.h"

#include <cmath>
#include <cstdio>

void ReplayDeviations::print(const std::string& name) const {
  displacement.print(name + " displacement");
  velocity.print(name + " velocity");
  force.print(name + " spring F,SF");
  stroke.print(name + " spring STROKE");
  if (friction.scale > 0.0) friction.print(name + " spring FF");
  std::printf("[agreement] %-58s %ld rows compared\n", name.c_str(), rows);
}

bool RowSample::compared(double time) const {
  if (interval <= 0.0) return true;
  const long k = std::lround(time / interval);
  if (k < first || k % every == 0) return true;
  for (const auto& [a, b] : windows)
    if (a <= time && time <= b) return true;
  return false;
}

long RowSample::expected_rows(double last_time) const {
  if (interval <= 0.0) return -1;
  long n = 0;
  for (long k = 1; k <= std::lround(last_time / interval); ++k) n += compared(double(k) * interval) ? 1 : 0;
  return n;
}

ReplayDeviations replay_against(reference::LeapFrog& model, const oracle::History& h, double step,
                                const std::vector<std::string>& body_prefix, const RowSample& sample) {
  ReplayDeviations dev;
  auto has = [&](const std::string& c) { return h.cols.count(c) > 0; };
  const char* axes = "XYZ";
  for (std::size_t r = 1; r < h.rows(); ++r) {
    if (!sample.compared(h["TIME"][r])) continue;
    const long n = std::lround(h["TIME"][r] / step);
    while (model.steps() < n + 1) model.step();
    ++dev.rows;
    for (std::size_t i = 0; i < body_prefix.size(); ++i) {
      const auto& b = model.bodies()[i];
      for (int c = 0; c < 3; ++c) {
        const std::string px = body_prefix[i] + "P" + axes[c];
        if (has(px)) dev.displacement.add(b.x(c) - h[px][0], h[px][r] - h[px][0], r);
        const std::string vx = body_prefix[i] + "V" + axes[c];
        if (has(vx)) dev.velocity.add(b.v(c), h[vx][r], r);
        const std::string ox = body_prefix[i] + "O" + axes[c];
        if (has(ox)) dev.velocity.add(b.w(c), h[ox][r], r);
      }
    }
    for (std::size_t s = 0; s < model.springs().size(); ++s) {
      const std::string sp = "spr" + std::to_string(s) + "_";
      const auto& spr = model.springs()[s];
      if (has(sp + "F")) dev.force.add(spr.last.total, h[sp + "F"][r], r);
      if (has(sp + "SF")) dev.force.add(spr.last.elastic, h[sp + "SF"][r], r);
      if (has(sp + "STROKE")) dev.stroke.add(spr.state.stroke, h[sp + "STROKE"][r], r);
      if (has(sp + "FF")) dev.friction.add(spr.state.friction_force, h[sp + "FF"][r], r);
    }
  }
  return dev;
}
