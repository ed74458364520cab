// The bare client's exchange (issue 12, P5): only the socket I/O of MBDyn's messages, with plain
// blocking calls and nothing else (no timeouts, no decoding, zero loads). Used by
// `mbdyn_bench_peer client` (alone, back to back) and by `fix mbdyn/floor` (the same exchange
// inside a LAMMPS step, where fix mbdyn's is), so the bench measures the floor fix mbdyn is held to.
#pragma once

#include <cstdint>
#include <vector>

#include "blocking_socket.h"
#include "wire_format.h"

namespace dembridge::mbdyn::bench {

class BareExchange {
 public:
  // Connects (retrying up to connect_timeout_s), negotiates `nodes` points with `rotation` (an
  // orientation matrix, or none for the messages of `external structural mapping`; no labels,
  // accelerations or reference node), reads the t0 kinematics. Throws std::runtime_error.
  BareExchange(const Place& place, std::uint32_t nodes, double connect_timeout_s,
               Rotation rotation = Rotation::OrientationMatrix);
  ~BareExchange();
  BareExchange(const BareExchange&) = delete;
  BareExchange& operator=(const BareExchange&) = delete;

  // One recv for the message (the rest, if it came in pieces, with more): false when the peer
  // sent 5 (end of simulation) instead of kinematics. Throws on a short message.
  bool receive();
  // One send of command 6 and zero loads.
  void send();
  // Reads the peer's 5 unless it came already, then closes (the peer then fails if it expected
  // more exchanges: its count of messages is exact). Never throws.
  void finish() noexcept;
  bool ended() const { return ended_; }

 private:
  int fd_ = -1;
  bool ended_ = false;
  std::vector<std::uint8_t> kin_, loads_;
};

}  // namespace dembridge::mbdyn::bench
