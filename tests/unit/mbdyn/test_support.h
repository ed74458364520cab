// Helpers shared by the MBDyn protocol tests: unique socket paths and the test peer run in a
// thread with a bounded join, so no test can hang.
#pragma once

#include <gtest/gtest.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <future>
#include <memory>
#include <string>

#include "mbdyn_test_peer.h"
#include "peer_session.h"

namespace dembridge::mbdyn::test {

inline std::string unique_socket_path(const std::string& tag) {
  static std::atomic<int> counter{0};
  return "/tmp/dembridge-mbdyn-" + std::to_string(::getpid()) + "-" + tag + "-" +
         std::to_string(counter++) + ".sock";
}

// Runs the test peer in its own thread.
class PeerThread {
 public:
  // When the test peer is the server, the constructor returns once it listens, and port() is
  // the bound TCP port (or -1 for Unix).
  explicit PeerThread(testpeer::PeerSetup setup) {
    auto listening = std::make_shared<std::promise<int>>();
    std::future<int> port = listening->get_future();
    const bool server = setup.mbdyn_creates_socket;
    setup.on_listening = [listening](int p) { listening->set_value(p); };
    future_ = std::async(std::launch::async, testpeer::run_mbdyn_test_peer, std::move(setup));
    if (server && port.wait_for(std::chrono::seconds(10)) == std::future_status::ready) port_ = port.get();
  }
  int port() const { return port_; }
  // Waits at most timeout_s; the test peer's own timeouts make it end well before.
  testpeer::PeerOutcome join(double timeout_s = 60.0) {
    if (future_.wait_for(std::chrono::duration<double>(timeout_s)) != std::future_status::ready) {
      ADD_FAILURE() << "test peer did not finish within " << timeout_s << " s";
    }
    return future_.get();
  }

 private:
  std::future<testpeer::PeerOutcome> future_;
  int port_ = -1;
};

inline testpeer::Orientation to_peer(Rotation r) {
  switch (r) {
    case Rotation::None: return testpeer::Orientation::None;
    case Rotation::OrientationVector: return testpeer::Orientation::Vector;
    case Rotation::OrientationMatrix: return testpeer::Orientation::Matrix;
    case Rotation::Euler123: return testpeer::Orientation::Euler123;
  }
  return testpeer::Orientation::Matrix;
}

inline testpeer::ElementShape to_peer(const NodalConfig& c) {
  testpeer::ElementShape s;
  s.nodes = c.num_points;
  s.orientation = to_peer(c.rotation);
  s.labels = c.labels;
  s.accelerations = c.accelerations;
  s.reference_node = c.reference_node;
  return s;
}

// Matching setups of both sides on a fresh Unix socket.
struct Pair {
  testpeer::PeerSetup peer;
  SessionOptions session;
};

inline Pair make_pair_setup(const NodalConfig& c, Coupling coupling, const std::string& tag) {
  Pair p;
  const std::string path = unique_socket_path(tag);
  p.peer.place.unix_path = path;
  p.peer.shape = to_peer(c);
  p.peer.coupling = coupling == Coupling::Loose   ? testpeer::CouplingMode::Loose
                    : coupling == Coupling::Tight ? testpeer::CouplingMode::Tight
                                                  : testpeer::CouplingMode::None;
  p.peer.accept_timeout_s = 10;
  p.peer.io_timeout_s = 10;
  p.session.endpoint = Endpoint::unix_path(path);
  p.session.nodal = c;
  p.session.coupling = coupling;
  p.session.connect_timeout_s = 10;
  p.session.io_timeout_s = 10;
  return p;
}

inline double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace dembridge::mbdyn::test
