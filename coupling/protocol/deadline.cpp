#include "deadline.h"

#include <algorithm>

namespace dembridge::mbdyn {

Deadline::Deadline(double timeout_s) : infinite_(timeout_s < 0.0) {
  const auto now = std::chrono::steady_clock::now();
  end_ = infinite_ ? now
                   : now + std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                               std::chrono::duration<double>(timeout_s));
}

bool Deadline::expired() const {
  return !infinite_ && std::chrono::steady_clock::now() >= end_;
}

int Deadline::poll_timeout_ms() const {
  if (infinite_) return -1;
  const auto left = end_ - std::chrono::steady_clock::now();
  if (left <= std::chrono::steady_clock::duration::zero()) return 0;
  const auto us = std::chrono::duration_cast<std::chrono::microseconds>(left).count();
  // Round up so we never spin on a 0 ms poll before the deadline; cap to fit an int.
  return static_cast<int>(std::min<long long>((us + 999) / 1000, 1 << 30));
}

}  // namespace dembridge::mbdyn
