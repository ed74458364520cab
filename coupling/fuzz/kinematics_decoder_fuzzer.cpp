// Fuzz target for what MBDyn can send us (issue 6): the kinematics decoder on its own, and the
// whole PeerSession state machine reading an arbitrary byte stream from a socket pair.
// Any exception other than ProtocolError, any crash or sanitizer report is a bug.
#include <sys/socket.h>
#include <unistd.h>

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdlib>

#include "nodal_message.h"
#include "peer_session.h"
#include "protocol_error.h"

using namespace dembridge::mbdyn;

namespace {

NodalConfig config_from(std::uint8_t selector, std::uint8_t count) {
  static const Rotation rotations[4] = {Rotation::None, Rotation::OrientationVector,
                                        Rotation::OrientationMatrix, Rotation::Euler123};
  NodalConfig c;
  c.rotation = rotations[selector & 3];
  c.labels = selector & 4;
  c.accelerations = selector & 8;
  c.reference_node = selector & 16;
  c.num_points = count % 5;
  return c;
}

void check(bool ok) {
  if (!ok) std::abort();
}

// Properties every successfully decoded message must have.
void check_kinematics(const NodalConfig& c, const Kinematics& k) {
  const std::size_t n = c.num_points;
  check(k.num_points() == n && k.v.size() == 3 * n);
  check(k.orientation.size() == (c.has_rotation() ? c.rotation_doubles() * n : 0));
  check(k.labels.size() == (c.labels ? n : 0));
  for (double v : k.x) check(std::isfinite(v));
  for (double v : k.v) check(std::isfinite(v));
  for (std::size_t i = 0; i < n; ++i) {
    const Matrix3 R = k.rotation_matrix(i);
    // Vector and Euler formats always give a rotation; a raw matrix is passed through.
    if (c.rotation == Rotation::OrientationVector || c.rotation == Rotation::Euler123) {
      for (int a = 0; a < 3; ++a)
        for (int b = 0; b < 3; ++b) {
          double dot = 0;
          for (int j = 0; j < 3; ++j) dot += R[3 * j + a] * R[3 * j + b];
          // Huge but finite angles lose precision in sin/cos; orthonormality stays near 1e-12.
          check(std::fabs(dot - (a == b ? 1.0 : 0.0)) < 1e-9);
        }
    }
  }
}

void fuzz_decoder(const NodalConfig& c, const std::uint8_t* data, std::size_t size) {
  try {
    check_kinematics(c, decode_kinematics_message(c, data, size));
  } catch (const ProtocolError&) {
  }
  try {
    NodalConfig::from_flags(size >= 4 ? data[0] | data[1] << 8 | data[2] << 16 | std::uint32_t(data[3]) << 24 : 0,
                            c.num_points);
  } catch (const ProtocolError&) {
  }
}

// MBDyn's side of a socket pair replays the input; we answer every kinematics message.
void fuzz_session(const NodalConfig& c, bool tight, const std::uint8_t* data, std::size_t size) {
  int fds[2];
  if (::socketpair(AF_UNIX, SOCK_STREAM, 0, fds) != 0) return;
  std::size_t written = 0;
  while (written < size) {
    const ssize_t rc = ::send(fds[1], data + written, size - written, MSG_NOSIGNAL | MSG_DONTWAIT);
    if (rc <= 0) break;
    written += static_cast<std::size_t>(rc);
  }
  ::shutdown(fds[1], SHUT_WR);  // EOF after the input
  SessionOptions o;
  o.nodal = c;
  o.coupling = tight ? Coupling::Tight : Coupling::Loose;
  o.io_timeout_s = 0.05;
  o.abort_timeout_s = 0.01;
  try {
    PeerSession s(SocketTransport(fds[0], false, "fuzz socketpair"), o);
    for (int i = 0; i < 64; ++i) {
      const Received r = s.receive();
      if (!r.is_kinematics()) break;
      check_kinematics(c, s.kinematics());
      if (i % 3 == 2)
        s.send_converged_keep_loads();
      else
        s.send_loads(Loads(c), !tight || i % 3 == 1);
    }
  } catch (const ProtocolError&) {
  }
  ::close(fds[1]);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 2) return 0;
  const NodalConfig c = config_from(data[0], data[1]);
  fuzz_decoder(c, data + 2, size - 2);
  if (size <= 4096) fuzz_session(c, data[0] & 32, data + 2, size - 2);
  return 0;
}
