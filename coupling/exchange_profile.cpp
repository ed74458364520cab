#include "exchange_profile.h"

#include <time.h>

#include <algorithm>
#include <cstdio>

namespace dembridge {

namespace {
double seconds(clockid_t id)
{
  timespec t{};
  clock_gettime(id, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}
}  // namespace

ExchangeProfile::Stamp ExchangeProfile::now()
{
  return {seconds(CLOCK_MONOTONIC), seconds(CLOCK_THREAD_CPUTIME_ID)};
}

ExchangeProfile::Stamp ExchangeProfile::process_now()
{
  return {seconds(CLOCK_MONOTONIC), seconds(CLOCK_PROCESS_CPUTIME_ID)};
}

void ExchangeProfile::start_run()
{
  if (!on_) return;
  sum_ = {};
  timed_ = steps_ = receives_ = ready_ = 0;
  ready_cpu_ = 0;
  timing_ = false;
  // What one reading adds to a lap: the minimum over a few back-to-back pairs (the least disturbed).
  reading_ = {1e9, 1e9};
  for (int i = 0; i < 32; ++i) {
    const Stamp a = now(), b = now();
    reading_.wall = std::min(reading_.wall, b.wall - a.wall);
    reading_.cpu = std::min(reading_.cpu, b.cpu - a.cpu);
  }
  run0_ = process_now();
}

void ExchangeProfile::start_step()
{
  if (!on_) return;
  ++steps_;
  rng_ ^= rng_ << 13;  // xorshift64
  rng_ ^= rng_ >> 7;
  rng_ ^= rng_ << 17;
  timing_ = rng_ % kStride == 0;
  if (timing_) ++timed_;
}

void ExchangeProfile::lap(Phase p)
{
  if (!timing_) return;
  const Stamp t = now();
  const double wall = t.wall - mark_.wall - reading_.wall, cpu = t.cpu - mark_.cpu - reading_.cpu;
  sum_[p].wall += wall;
  sum_[p].cpu += cpu;
  if (p == Receive) {
    ++receives_;
    if (wall - cpu < kWaited) {
      ++ready_;
      ready_cpu_ += cpu;
    }
  }
  mark_ = t;
}

ExchangeProfile::Stamp ExchangeProfile::phase(Phase p) const
{
  if (timed_ == 0) return {};
  return {sum_[p].wall / timed_, sum_[p].cpu / timed_};
}

std::string ExchangeProfile::summary(const std::string &who) const
{
  if (!on_ || timed_ == 0 || steps_ == 0) return "";
  const Stamp end = process_now();
  const double run_wall = (end.wall - run0_.wall) / steps_, run_cpu = (end.cpu - run0_.cpu) / steps_;
  Stamp fix;
  for (int p = 0; p < kPhases; ++p) {
    fix.wall += phase(static_cast<Phase>(p)).wall;
    fix.cpu += phase(static_cast<Phase>(p)).cpu;
  }
  const double wait = std::max(0.0, phase(Receive).wall - phase(Receive).cpu);
  const double own_wall = fix.wall - wait;
  auto us = [](double s) { return 1e6 * s; };
  char buf[1024];
  std::snprintf(buf, sizeof buf,
                "%s profile: %lld steps, %lld timed; per step: fix cpu %.2f us, fix wall %.2f us without "
                "%.2f us waiting for MBDyn (receive %.2f/%.2f, pose %.2f/%.2f, loads %.2f/%.2f, end_of_step "
                "%.2f/%.2f us wall/cpu); run cpu %.2f us, run wall %.2f us; fix share %.3f %% of the cpu, "
                "%.3f %% of the wall, waiting %.3f %% of the wall; %lld of %lld timed receives found the message "
                "there (%.2f us cpu each); clock reading %.3f us wall, %.3f us cpu (taken off)\n",
                who.c_str(), steps_, timed_, us(fix.cpu), us(own_wall), us(wait), us(phase(Receive).wall),
                us(phase(Receive).cpu), us(phase(Pose).wall), us(phase(Pose).cpu), us(phase(Loads).wall),
                us(phase(Loads).cpu), us(phase(EndOfStep).wall), us(phase(EndOfStep).cpu), us(run_cpu),
                us(run_wall), 100 * fix.cpu / run_cpu, 100 * own_wall / run_wall, 100 * wait / run_wall, ready_,
                receives_, us(ready_receive_cpu()), us(reading_.wall), us(reading_.cpu));
  return buf;
}

}  // namespace dembridge
