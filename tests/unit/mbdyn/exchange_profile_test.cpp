// fix mbdyn's `profile yes` timers (coupling/exchange_profile.*): a phase that sleeps is wall time
// spent waiting, not CPU; a phase that spins is CPU. References: the sleep's requested length (a
// lower bound of the wall time) and the process CPU clock of std::clock() (this test has one thread).
#include <gtest/gtest.h>

#include <chrono>
#include <ctime>
#include <thread>

#include "exchange_profile.h"

namespace {

using dembridge::ExchangeProfile;

void spin_cpu(double seconds) {
  const std::clock_t start = std::clock();
  while (static_cast<double>(std::clock() - start) / CLOCKS_PER_SEC < seconds) {
  }
}

TEST(ExchangeProfile, SleepIsWaitingAndSpinIsCpu) {
  ExchangeProfile p;
  p.enable();
  p.start_run();
  const int steps = 400;  // one in 8 timed: P(none) = (7/8)^400, nil
  for (int s = 0; s < steps; ++s) {
    p.start_step();
    p.begin();
    std::this_thread::sleep_for(std::chrono::microseconds(200));  // "waiting for MBDyn's message"
    p.lap(ExchangeProfile::Receive);
    spin_cpu(50e-6);
    p.lap(ExchangeProfile::Loads);
  }
  ASSERT_GT(p.timed_steps(), 0);
  EXPECT_LT(p.timed_steps(), steps);
  const auto receive = p.phase(ExchangeProfile::Receive), loads = p.phase(ExchangeProfile::Loads);
  EXPECT_GE(receive.wall, 190e-6);               // slept at least 200 us (less a reading's cost)
  EXPECT_LT(receive.cpu, 0.5 * receive.wall);    // sleeping costs (almost) no CPU
  EXPECT_GE(loads.cpu, 40e-6);                   // spun 50 us of process CPU (clock() ticks in us)
  EXPECT_GE(loads.wall, loads.cpu - 1e-6);       // CPU time cannot exceed wall time
  EXPECT_EQ(p.ready_receives(), 0);              // every receive waited 200 us
  EXPECT_EQ(p.timed_receives(), p.timed_steps());
  const std::string line = p.summary("Fix mbdyn (id M)");
  EXPECT_EQ(line.rfind("Fix mbdyn (id M) profile: 400 steps, ", 0), 0u) << line;
  EXPECT_NE(line.find("fix share"), std::string::npos) << line;
}

TEST(ExchangeProfile, DisabledMeasuresNothing) {
  ExchangeProfile p;
  p.start_run();
  for (int s = 0; s < 100; ++s) {
    p.start_step();
    p.begin();
    p.lap(ExchangeProfile::Receive);
  }
  EXPECT_EQ(p.timed_steps(), 0);
  EXPECT_EQ(p.summary("Fix mbdyn (id M)"), "");
}

TEST(ExchangeProfile, ARunRestartsTheFigures) {
  ExchangeProfile p;
  p.enable();
  p.start_run();
  for (int s = 0; s < 200; ++s) {
    p.start_step();
    p.begin();
    spin_cpu(20e-6);
    p.lap(ExchangeProfile::Pose);
  }
  ASSERT_GT(p.timed_steps(), 0);
  p.start_run();
  EXPECT_EQ(p.timed_steps(), 0);
  EXPECT_EQ(p.phase(ExchangeProfile::Pose).cpu, 0.0);
}

}  // namespace
