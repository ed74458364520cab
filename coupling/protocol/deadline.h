// A point in time after which a blocking call gives up (spec P4: a timeout on every blocking call).
#pragma once

#include <chrono>

namespace dembridge::mbdyn {

class Deadline {
 public:
  // timeout_s < 0 means "never" (MBDyn's own behaviour, only for explicit opt-in).
  explicit Deadline(double timeout_s);
  bool infinite() const { return infinite_; }
  bool expired() const;
  // Milliseconds left for poll(): -1 when infinite, 0 when expired, rounded up otherwise.
  int poll_timeout_ms() const;

 private:
  bool infinite_;
  std::chrono::steady_clock::time_point end_;
};

}  // namespace dembridge::mbdyn
