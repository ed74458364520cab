// The two ends of the exchange benchmark (bench/run_mbdyn_exchange_bench.py, issue 12 P5): a
// fast MBDyn-side peer that answers instantly with one prebuilt kinematics message, and a minimal
// client that does nothing but the socket I/O of the same messages. Timing fix mbdyn and the
// bare client against the same peer cancels the peer's own cost.
#pragma once

#include <array>
#include <cstdint>
#include <string>

#include "blocking_socket.h"
#include "wire_format.h"

namespace dembridge::mbdyn::bench {

struct BenchShape {
  std::uint32_t nodes = 100;  // no labels, accelerations or reference node
  // Orientation matrix (external structural), or none: the messages of `external structural
  // mapping` (positions and velocities of the mapped points; loads = forces at them).
  bool orientation_none = false;
  std::array<double, 3> origin{0, 0, 0};   // node k sits at origin + k * spacing, at rest
  std::array<double, 3> spacing{0.02, 0, 0};
  // grid > 0: node k sits at origin + (k % grid) spacing_x ex + (k / grid) spacing_y ey instead
  // (the vertices of a flat triangle mesh, for `fix mbdyn ... mapping`).
  std::uint32_t grid = 0;

  Rotation rotation() const { return orientation_none ? Rotation::None : Rotation::OrientationMatrix; }
  std::array<double, 3> position(std::uint32_t k) const;
};

// MBDyn's side (`create, yes`): accepts one client, checks its negotiation, sends `messages`
// kinematics messages (command 6 and payload in one write) each answered by 6 and loads, then 5.
// Prints "mbdyn_bench_peer: listening ..." once it listens. Returns an exit status.
int run_fast_peer(const Place& place, const BenchShape& shape, long messages);

// The bare client: negotiates, then reads each kinematics message and answers zero loads until
// the 5. Prints the wall and CPU time per exchange after the t0 one. Returns an exit status.
int run_bare_client(const Place& place, const BenchShape& shape);

}  // namespace dembridge::mbdyn::bench
