// fix mbdyn `profile yes` (issue 12, P5): the fix's own cost inside a coupled run, measured rather
// than taken as "coupled deck minus plain deck". Wall time (steady clock) and this thread's CPU
// time around each phase of the fix's per-step work; the receive phase's wall minus its CPU is the
// time spent blocked waiting for MBDyn's message. On this kind of VM a thread-CPU clock reading is
// a system call (~3 us), so only a random one step in kStride is timed (no aliasing with
// sub-steps or neighbour rebuilds), and the cost of a reading is measured and taken off each phase.
#pragma once

#include <array>
#include <cstdint>
#include <string>

namespace dembridge {

class ExchangeProfile {
 public:
  enum Phase { Receive, Pose, Loads, EndOfStep, kPhases };
  static constexpr int kStride = 8;  // one step in 8, on average, is timed

  void enable() { on_ = true; }
  bool enabled() const { return on_; }
  // A run's loop starts (fix setup): zeroes the sums, calibrates a reading, marks the process clocks.
  void start_run();
  // At the start of a step's first fix call: decides whether this step is timed.
  void start_step();
  // The fix starts a piece of its work (reads the clocks when the step is timed).
  void begin() {
    if (timing_) mark_ = now();
  }
  // The time since begin() or the previous lap() goes to phase p (less the cost of one reading).
  void lap(Phase p);
  // The run's summary for the log (empty when not enabled or nothing was timed).
  std::string summary(const std::string &who) const;

  // Figures per timed step, seconds; public for the unit test.
  struct Stamp {
    double wall = 0, cpu = 0;
  };
  Stamp phase(Phase p) const;
  long long timed_steps() const { return timed_; }
  // Timed receives that found MBDyn's message already there (wall - cpu below kWaited), and their
  // mean CPU: the receive's cost without a sleep and wake-up.
  static constexpr double kWaited = 5e-6;
  long long ready_receives() const { return ready_; }
  long long timed_receives() const { return receives_; }
  double ready_receive_cpu() const { return ready_ ? ready_cpu_ / ready_ : 0.0; }
  static Stamp now();          // steady clock, CLOCK_THREAD_CPUTIME_ID
  static Stamp process_now();  // steady clock, CLOCK_PROCESS_CPUTIME_ID

 private:
  bool on_ = false, timing_ = false;
  std::uint64_t rng_ = 0x9e3779b97f4a7c15ULL;
  Stamp mark_, run0_, reading_;
  std::array<Stamp, kPhases> sum_{};
  long long timed_ = 0, steps_ = 0, receives_ = 0, ready_ = 0;
  double ready_cpu_ = 0;
};

}  // namespace dembridge
