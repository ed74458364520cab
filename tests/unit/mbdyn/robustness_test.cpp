// Failure cases of issue 6, each bounded by a timeout: nobody to talk to, MBDyn dies, garbage
// command byte, short message, NaN kinematics, and the clean abort (5) on the way out.
#include <gtest/gtest.h>
#include <sys/socket.h>

#include <chrono>
#include <cstring>
#include <thread>
#include <typeinfo>
#include <utility>

#include "protocol_error.h"
#include "test_support.h"

using namespace dembridge::mbdyn;
using dembridge::mbdyn::test::PeerThread;
using Clock = std::chrono::steady_clock;

namespace {

NodalConfig two_matrix_nodes_with_labels() {
  NodalConfig c;
  c.num_points = 2;
  c.rotation = Rotation::OrientationMatrix;
  c.labels = true;
  return c;
}

// Runs loose exchanges until the library throws; returns the exception text and its type name.
template <class E>
std::string run_until(PeerSession& s, int max_messages = 100) {
  try {
    for (int i = 0; i < max_messages; ++i) {
      if (!s.receive().is_kinematics()) break;
      s.send_loads(Loads(s.config()), true);
    }
  } catch (const E& e) {
    return e.what();
  }
  ADD_FAILURE() << "expected " << typeid(E).name();
  return "";
}

bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

}  // namespace

TEST(Robustness, MbdynNeverCreatesTheUnixSocket) {
  SessionOptions o;
  o.endpoint = Endpoint::unix_path(test::unique_socket_path("never"));
  o.nodal = two_matrix_nodes_with_labels();
  o.connect_timeout_s = 1.0;
  const auto t0 = Clock::now();
  try {
    PeerSession::open(o);
    FAIL() << "expected TimeoutError";
  } catch (const TimeoutError& e) {
    EXPECT_TRUE(contains(e.what(), "expected MBDyn to accept within 1 s")) << e.what();
    EXPECT_TRUE(contains(e.what(), "No such file or directory")) << e.what();
  }
  const double elapsed = test::seconds_since(t0);
  EXPECT_GE(elapsed, 1.0);
  EXPECT_LT(elapsed, 1.5);
}

TEST(Robustness, MbdynNeverListensOnTcp) {
  // Port 1 on loopback refuses: ECONNREFUSED is retried until the deadline.
  SessionOptions o;
  o.endpoint = Endpoint::tcp("127.0.0.1", 1);
  o.nodal = two_matrix_nodes_with_labels();
  o.connect_timeout_s = 0.5;
  const auto t0 = Clock::now();
  EXPECT_THROW(PeerSession::open(o), TimeoutError);
  const double elapsed = test::seconds_since(t0);
  EXPECT_GE(elapsed, 0.5);
  EXPECT_LT(elapsed, 1.0);
}

TEST(Robustness, MbdynNeverConnectsInCreateNoRole) {
  SessionOptions o;
  o.endpoint = Endpoint::unix_path(test::unique_socket_path("never-no"));
  o.role = SocketRole::PeerCreates;
  o.nodal = two_matrix_nodes_with_labels();
  o.connect_timeout_s = 0.5;
  const auto t0 = Clock::now();
  try {
    PeerSession::open(o);
    FAIL() << "expected TimeoutError";
  } catch (const TimeoutError& e) {
    EXPECT_TRUE(contains(e.what(), "nobody connected")) << e.what();
  }
  EXPECT_LT(test::seconds_since(t0), 1.0);
}

TEST(Robustness, MbdynDiesMidRun) {
  for (bool tcp : {false, true}) {
    SCOPED_TRACE(tcp ? "tcp" : "unix");
    auto pair = test::make_pair_setup(two_matrix_nodes_with_labels(), Coupling::Loose, "dies");
    pair.peer.steps = 20;
    pair.peer.fault = testpeer::Fault::DieMidRun;
    pair.peer.fault_message = 5;
    if (tcp) pair.peer.place.tcp_port = 0;
    PeerThread peer(pair.peer);
    if (tcp) pair.session.endpoint = Endpoint::tcp("127.0.0.1", static_cast<std::uint16_t>(peer.port()));
    PeerSession s = PeerSession::open(pair.session);
    const auto t0 = Clock::now();
    const std::string what = run_until<PeerClosedError>(s);
    EXPECT_LT(test::seconds_since(t0), 2.0);
    EXPECT_TRUE(contains(what, "without sending 5")) << what;
    EXPECT_EQ(s.messages_received(), 5u);
    peer.join();
  }
}

TEST(Robustness, GarbageCommandByteIsRejectedAndMbdynToldToStop) {
  auto pair = test::make_pair_setup(two_matrix_nodes_with_labels(), Coupling::Loose, "garbage");
  pair.peer.steps = 10;
  pair.peer.fault = testpeer::Fault::GarbageCommand;
  pair.peer.fault_message = 3;
  PeerThread peer(pair.peer);
  PeerSession s = PeerSession::open(pair.session);
  const std::string what = run_until<MalformedMessageError>(s);
  EXPECT_TRUE(contains(what, "expected 2, 5 or 6, received 66 (unknown)")) << what;
  EXPECT_TRUE(peer.join().abort_received_after_fault);
}

TEST(Robustness, ShortMessageThenCloseNamesTheMissingBytes) {
  const NodalConfig c = two_matrix_nodes_with_labels();
  auto pair = test::make_pair_setup(c, Coupling::Loose, "short-close");
  pair.peer.fault = testpeer::Fault::ShortPayloadThenClose;
  pair.peer.fault_message = 2;
  PeerThread peer(pair.peer);
  PeerSession s = PeerSession::open(pair.session);
  const std::string what = run_until<PeerClosedError>(s);
  const std::size_t full = c.kinematics_payload_bytes();
  EXPECT_TRUE(contains(what, "received " + std::to_string(full / 2) + " of " + std::to_string(full) + " bytes")) << what;
  peer.join();
}

TEST(Robustness, ShortMessageThenStallTimesOutAndSendsAbort) {
  const NodalConfig c = two_matrix_nodes_with_labels();
  auto pair = test::make_pair_setup(c, Coupling::Loose, "short-stall");
  pair.peer.fault = testpeer::Fault::ShortPayloadThenStall;
  pair.peer.fault_message = 2;
  pair.session.io_timeout_s = 0.5;
  PeerThread peer(pair.peer);
  PeerSession s = PeerSession::open(pair.session);
  const auto t0 = Clock::now();
  const std::string what = run_until<TimeoutError>(s);
  const double elapsed = test::seconds_since(t0);
  EXPECT_GE(elapsed, 0.5);
  EXPECT_LT(elapsed, 1.5);
  const std::size_t full = c.kinematics_payload_bytes();
  EXPECT_TRUE(contains(what, "received " + std::to_string(full / 2) + " of " + std::to_string(full) + " bytes")) << what;
  EXPECT_TRUE(peer.join().abort_received_after_fault);
}

TEST(Robustness, NanInKinematicsIsRejectedNamingFieldAndNode) {
  auto pair = test::make_pair_setup(two_matrix_nodes_with_labels(), Coupling::Loose, "nan");
  pair.peer.fault = testpeer::Fault::NanInKinematics;
  pair.peer.fault_message = 4;
  PeerThread peer(pair.peer);
  PeerSession s = PeerSession::open(pair.session);
  const std::string what = run_until<MalformedMessageError>(s);
  EXPECT_TRUE(contains(what, "field 'v' of point 1 (label 20), component 1")) << what;
  EXPECT_EQ(s.messages_received(), 4u);
  EXPECT_TRUE(peer.join().abort_received_after_fault);
}

TEST(Robustness, DestroyingASessionMidRunSendsAbort) {
  // E.g. LAMMPS hits an error between receive and answer: MBDyn must hear 5, not hang.
  auto pair = test::make_pair_setup(two_matrix_nodes_with_labels(), Coupling::Loose, "dtor");
  pair.peer.steps = 10;
  PeerThread peer(pair.peer);
  {
    PeerSession s = PeerSession::open(pair.session);
    ASSERT_TRUE(s.receive().is_kinematics());
  }
  const auto out = peer.join();
  EXPECT_EQ(out.answers, std::vector<std::uint8_t>{5});
  EXPECT_EQ(out.exit_status, 2) << out.log;
}

TEST(Robustness, WritingToAClosedPeerThrowsInsteadOfSigpipe) {
  int fds[2];
  ASSERT_EQ(::socketpair(AF_UNIX, SOCK_STREAM, 0, fds), 0);
  SocketTransport t(fds[0], false, "socketpair");
  ::close(fds[1]);
  const std::uint8_t bytes[4] = {6, 0, 0, 0};
  EXPECT_THROW(t.write_all(bytes, sizeof bytes, 1.0, "loads"), PeerClosedError);
}

TEST(Robustness, MbdynAbortsMidRunIsANormalEnd) {
  // MBDyn's 5 before the planned number of steps (e.g. its own error) ends the session cleanly.
  auto pair = test::make_pair_setup(two_matrix_nodes_with_labels(), Coupling::Tight, "maxit");
  pair.peer.steps = 10;
  pair.peer.max_iterations = 4;
  pair.peer.model.gravity = {0, 0, -9.81};  // non-zero initial residual: start-up exchange (T2)
  PeerThread peer(pair.peer);
  PeerSession s = PeerSession::open(pair.session);
  int messages = 0;
  for (;;) {
    const Received r = s.receive();
    if (!r.is_kinematics()) break;
    ++messages;
    s.send_loads(Loads(s.config()), r.step == 0);  // never converges after t0
  }
  EXPECT_EQ(messages, 1 + 1 + 4);  // t0, the prediction, one iterate per Newton update
  const auto out = peer.join();
  EXPECT_EQ(out.exit_status, 1);
  EXPECT_TRUE(contains(out.log, "Max iterations number 4")) << out.log;
}

namespace {
bool has_payload(std::uint8_t cmd) { return cmd == 6; }
}  // namespace

TEST(Robustness, SilentPeerTimesOutInTheBlockingFirstReceive) {
  // A message's first recvmsg blocks in the kernel (SO_RCVTIMEO): a peer that sends nothing must
  // still end it at the io timeout, with the usual wording; io timeout 0 must not block at all.
  for (double timeout : {0.4, 0.0}) {
    SCOPED_TRACE(timeout);
    int fds[2];
    ASSERT_EQ(::socketpair(AF_UNIX, SOCK_STREAM, 0, fds), 0);
    SocketTransport t(fds[0], false, "socketpair");
    std::uint8_t cmd = 0, payload[48];
    const auto t0 = Clock::now();
    try {
      t.read_message(cmd, payload, sizeof payload, has_payload, timeout, "a command byte", "payload");
      ADD_FAILURE() << "expected a TimeoutError";
    } catch (const TimeoutError& e) {
      EXPECT_TRUE(contains(e.what(), "waiting for a command byte")) << e.what();
      EXPECT_TRUE(contains(e.what(), "received 0 of 1 bytes")) << e.what();
    }
    const double elapsed = test::seconds_since(t0);
    EXPECT_GE(elapsed, timeout);
    EXPECT_LT(elapsed, timeout + 1.0);
    ::close(fds[1]);
  }
}

TEST(Robustness, MessageArrivingInPiecesIsReadWhole) {
  // MBDyn writes the command byte and the payload separately: the blocking first recvmsg returns
  // the byte alone, the rest is waited for in poll().
  int fds[2];
  ASSERT_EQ(::socketpair(AF_UNIX, SOCK_STREAM, 0, fds), 0);
  SocketTransport t(fds[0], false, "socketpair");
  std::uint8_t sent[49];
  for (int i = 0; i < 49; ++i) sent[i] = static_cast<std::uint8_t>(i == 0 ? 6 : 100 + i);
  std::thread writer([&] {
    for (const auto& piece : {std::pair<int, int>{0, 1}, {1, 20}, {21, 28}}) {
      std::this_thread::sleep_for(std::chrono::milliseconds(30));
      ASSERT_EQ(::send(fds[1], sent + piece.first, piece.second, 0), piece.second);
    }
  });
  std::uint8_t cmd = 0, payload[48] = {};
  t.read_message(cmd, payload, sizeof payload, has_payload, 5.0, "a command byte", "payload");
  writer.join();
  EXPECT_EQ(cmd, 6);
  EXPECT_EQ(0, std::memcmp(payload, sent + 1, 48));
  ::close(fds[1]);
}
