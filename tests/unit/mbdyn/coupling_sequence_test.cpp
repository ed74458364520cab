// Message sequences of loose, tight and none coupling (spec §5) and the 4 / 5 answers, with the
// step bookkeeping of Received checked against what the test peer counted.
#include <gtest/gtest.h>

#include <chrono>
#include <cstdio>
#include <stdexcept>

#include "protocol_error.h"
#include "test_support.h"

using namespace dembridge::mbdyn;
using dembridge::mbdyn::test::PeerThread;

namespace {

NodalConfig two_matrix_nodes() {
  NodalConfig c;
  c.num_points = 2;
  c.rotation = Rotation::OrientationMatrix;
  return c;
}

}  // namespace

TEST(CouplingSequence, LooseIsOneExchangePerStepPlusTheT0Exchange) {
  NodalConfig c = two_matrix_nodes();
  c.num_points = 3;  // odd N with labels: the pad word must be there both ways
  c.labels = true;
  c.reference_node = true;
  auto pair = test::make_pair_setup(c, Coupling::Loose, "loose");
  pair.peer.steps = 20;
  PeerThread peer(pair.peer);
  PeerSession s = PeerSession::open(pair.session);
  std::vector<Kinematics> seen;
  for (std::uint64_t expected = 0;; ++expected) {
    const Received r = s.receive();
    if (!r.is_kinematics()) break;
    EXPECT_EQ(r.message_index, expected);
    EXPECT_EQ(r.step, expected);  // loose: message k is step k, message 0 is t0 (spec P7)
    EXPECT_EQ(r.iteration, 0u);
    EXPECT_TRUE(r.starts_new_step);
    EXPECT_EQ(s.kinematics().command, Command::RegularDataAndGotoNextStep);
    EXPECT_EQ(s.kinematics().labels, (std::vector<std::uint32_t>{10, 20, 30}));
    EXPECT_EQ(s.kinematics().reference.label, 1u);
    seen.push_back(s.kinematics());
    // Labels are left empty: the session echoes the received ones (spec P10).
    s.send_loads(Loads(c), true);
  }
  EXPECT_TRUE(s.finished());
  ASSERT_EQ(seen.size(), 21u);
  // MBDyn's crank nicolson predictor (tests/data/mbdyn): step 1 sends v0 and x0 + dt v0.
  EXPECT_EQ(seen[1].v, seen[0].v);
  for (std::size_t j = 0; j < seen[0].x.size(); ++j)
    EXPECT_NEAR(seen[1].x[j], seen[0].x[j] + pair.peer.dt * seen[0].v[j], 1e-14);
  const auto out = peer.join();
  EXPECT_EQ(out.exit_status, 0) << out.log;
  EXPECT_EQ(out.kinematics_sent, 21);
  EXPECT_EQ(out.answers, std::vector<std::uint8_t>(21, 6));
}

TEST(CouplingSequence, LooseRefusesToAnswerTwo) {
  auto pair = test::make_pair_setup(two_matrix_nodes(), Coupling::Loose, "loose2");
  pair.peer.steps = 1;
  PeerThread peer(pair.peer);
  PeerSession s = PeerSession::open(pair.session);
  ASSERT_TRUE(s.receive().is_kinematics());
  EXPECT_THROW(s.send_loads(Loads(s.config()), false), std::logic_error);  // spec §5.1, P9
  EXPECT_THROW(s.receive(), std::logic_error);  // still owes an answer
  s.send_converged_keep_loads();                // 4 is a valid loose answer
  ASSERT_TRUE(s.receive().is_kinematics());
  s.send_loads(Loads(s.config()), true);
  EXPECT_FALSE(s.receive().is_kinematics());
  const auto out = peer.join();
  EXPECT_EQ(out.exit_status, 0) << out.log;
  EXPECT_EQ(out.answers, (std::vector<std::uint8_t>{4, 6}));
}

TEST(CouplingSequence, TightIteratesUntilThePeerDeclaresConvergence) {
  // 3 exchanges per step, t0 answered with 6 (spec T1): 1 + 3 x steps messages, all cmd 2.
  auto pair = test::make_pair_setup(two_matrix_nodes(), Coupling::Tight, "tight");
  pair.peer.steps = 10;
  pair.peer.model.gravity = {0, 0, -9.81};  // non-zero initial residual: start-up exchange (T2)
  PeerThread peer(pair.peer);
  PeerSession s = PeerSession::open(pair.session);
  std::uint64_t messages = 0;
  for (;;) {
    const Received r = s.receive();
    if (!r.is_kinematics()) break;
    ++messages;
    EXPECT_EQ(s.kinematics().command, Command::RegularData);
    if (r.message_index == 0) {
      EXPECT_EQ(r.step, 0u);
      s.send_loads(Loads(s.config()), true);
      continue;
    }
    EXPECT_EQ(r.step, (r.message_index - 1) / 3 + 1);
    EXPECT_EQ(r.iteration, (r.message_index - 1) % 3);
    EXPECT_EQ(r.starts_new_step, r.iteration == 0);
    if (r.iteration < 2)
      s.send_loads(Loads(s.config()), false);
    else if (r.step % 2)
      s.send_loads(Loads(s.config()), true);
    else
      s.send_converged_keep_loads();
  }
  EXPECT_EQ(messages, 31u);
  const auto out = peer.join();
  EXPECT_EQ(out.exit_status, 0) << out.log;
  EXPECT_EQ(out.kinematics_sent, 31);
  EXPECT_EQ(out.trajectory.size(), 11u);
}

TEST(CouplingSequence, TightT0AnsweredWithTwoIsRepeatedByMbdyn) {
  // spec T1: answering 2 at t0 with loads that change MBDyn's residual makes the derivatives
  // solve send t0 again; the session counts it as iteration 1 of step 0.
  auto pair = test::make_pair_setup(two_matrix_nodes(), Coupling::Tight, "tight-t0");
  pair.peer.steps = 1;
  pair.peer.model.gravity = {0, 0, -9.81};  // non-zero initial residual: start-up exchange (T2)
  PeerThread peer(pair.peer);
  PeerSession s = PeerSession::open(pair.session);
  Received r = s.receive();
  EXPECT_EQ(r.step, 0u);
  Loads push(s.config());
  push.set_force(0, {1.0, 0.0, 0.0});
  s.send_loads(push, false);
  r = s.receive();
  EXPECT_EQ(r.step, 0u);
  EXPECT_EQ(r.iteration, 1u);
  s.send_loads(Loads(s.config()), true);
  r = s.receive();
  EXPECT_EQ(r.step, 1u);
  EXPECT_TRUE(r.starts_new_step);
  s.send_loads(Loads(s.config()), true);
  EXPECT_FALSE(s.receive().is_kinematics());
  EXPECT_EQ(peer.join().exit_status, 0);
}

TEST(CouplingSequence, NoneIsAOneWayStream) {
  auto pair = test::make_pair_setup(two_matrix_nodes(), Coupling::None, "none");
  pair.peer.steps = 5;
  PeerThread peer(pair.peer);
  PeerSession s = PeerSession::open(pair.session);
  int messages = 0;
  for (;;) {
    const Received r = s.receive();
    if (!r.is_kinematics()) break;
    EXPECT_EQ(r.step, static_cast<std::uint64_t>(messages));
    ++messages;
    EXPECT_THROW(s.send_loads(Loads(s.config()), true), std::logic_error);
  }
  EXPECT_EQ(messages, 7);  // steps + 2, as the verified 1002 for 1000 steps (spec §5.3)
  const auto out = peer.join();
  EXPECT_EQ(out.exit_status, 0) << out.log;
  EXPECT_TRUE(out.answers.empty());
}

TEST(CouplingSequence, MismatchedCouplingModeIsDetectedAndMbdynStopped) {
  auto pair = test::make_pair_setup(two_matrix_nodes(), Coupling::Tight, "mismatch");
  pair.session.coupling = Coupling::Loose;
  PeerThread peer(pair.peer);
  PeerSession s = PeerSession::open(pair.session);
  try {
    s.receive();
    FAIL() << "expected MalformedMessageError";
  } catch (const MalformedMessageError& e) {
    EXPECT_NE(std::string(e.what()).find("loose coupling expects 6"), std::string::npos) << e.what();
  }
  const auto out = peer.join();
  EXPECT_EQ(out.answers, std::vector<std::uint8_t>{5}) << out.log;
  EXPECT_EQ(out.exit_status, 2) << out.log;
}

TEST(CouplingSequence, PeerStopRequestEndsMbdynAfterTheCurrentStep) {
  auto pair = test::make_pair_setup(two_matrix_nodes(), Coupling::Loose, "stop");
  pair.peer.steps = 50;
  PeerThread peer(pair.peer);
  PeerSession s = PeerSession::open(pair.session);
  for (int i = 0; i < 4; ++i) {
    ASSERT_TRUE(s.receive().is_kinematics());
    s.send_loads(Loads(s.config()), true);
  }
  ASSERT_EQ(s.receive().step, 4u);
  s.request_stop();
  EXPECT_FALSE(s.receive().is_kinematics());
  EXPECT_TRUE(s.finished());
  const auto out = peer.join();
  EXPECT_EQ(out.exit_status, 2) << out.log;  // "MBDyn was interrupted"
  EXPECT_EQ(out.trajectory.size(), 5u);      // t0 and steps 1..4, step 4 completed
  EXPECT_EQ(out.answers.back(), 5);
}

// A coupling continued by new processes on both sides (restart): the test peer saves its state when
// the peer stops it, a new test peer resumes from it, and a new session continued after the last
// answered step receives the next step first, with the bytes and the step counts of the unbroken run.
TEST(CouplingSequence, AContinuedSessionStartsAtTheStepAfterTheLastAnswer) {
  const NodalConfig c = two_matrix_nodes();
  auto answer = [&](PeerSession& s, std::uint64_t step) {
    Loads l(c);
    for (std::size_t j = 0; j < l.force.size(); ++j) l.force[j] = 0.25 * static_cast<double>(step + j);
    s.send_loads(l, true);
  };
  // the unbroken run: t0 and 8 steps
  auto whole = test::make_pair_setup(c, Coupling::Loose, "whole");
  whole.peer.steps = 8;
  PeerThread peer0(whole.peer);
  PeerSession s0 = PeerSession::open(whole.session);
  std::vector<std::vector<std::uint8_t>> unbroken;
  for (;;) {
    const Received r = s0.receive();
    if (!r.is_kinematics()) break;
    unbroken.push_back(s0.raw_payload());
    answer(s0, r.step);
  }
  const auto out0 = peer0.join();
  ASSERT_EQ(unbroken.size(), 9u);
  // the first part: steps up to 3 answered, step 4 refused with 5
  const std::string state = test::unique_socket_path("state") + ".txt";
  auto first = test::make_pair_setup(c, Coupling::Loose, "first");
  first.peer.steps = 8;
  first.peer.save_state = state;
  PeerThread peer1(first.peer);
  PeerSession s1 = PeerSession::open(first.session);
  for (std::uint64_t k = 0; k <= 3; ++k) {
    ASSERT_EQ(s1.receive().step, k);
    answer(s1, k);
  }
  ASSERT_EQ(s1.receive().step, 4u);
  s1.request_stop();
  EXPECT_FALSE(s1.receive().is_kinematics());
  EXPECT_EQ(peer1.join().exit_status, 2);
  // the continuation
  auto second = test::make_pair_setup(c, Coupling::Loose, "second");
  second.peer.steps = 8;
  second.peer.resume_state = state;
  PeerThread peer2(second.peer);
  PeerSession s2 = PeerSession::open(second.session);
  s2.continue_after_step(3);
  for (std::uint64_t k = 4;; ++k) {
    const Received r = s2.receive();
    if (!r.is_kinematics()) {
      EXPECT_EQ(k, 9u);
      break;
    }
    EXPECT_EQ(r.step, k);
    EXPECT_TRUE(r.starts_new_step);
    ASSERT_LT(k, unbroken.size());
    EXPECT_EQ(s2.raw_payload(), unbroken[k]) << "message of step " << k;
    answer(s2, r.step);
  }
  const auto out2 = peer2.join();
  EXPECT_EQ(out2.exit_status, 0) << out2.log;
  // the resumed peer's trajectory: the restored step 3, then steps 4..8, as the unbroken peer's
  ASSERT_EQ(out2.trajectory.size(), 6u);
  for (std::size_t i = 0; i < out2.trajectory.size(); ++i) {
    const auto &a = out2.trajectory[i], &b = out0.trajectory[i + 3];
    EXPECT_EQ(a.t, b.t);
    for (std::size_t n = 0; n < a.bodies.size(); ++n) {
      EXPECT_EQ(a.bodies[n].x, b.bodies[n].x);
      EXPECT_EQ(a.bodies[n].v, b.bodies[n].v);
      EXPECT_EQ(a.bodies[n].theta, b.bodies[n].theta);
    }
  }
  std::remove(state.c_str());
  EXPECT_THROW(s2.continue_after_step(1), std::logic_error);  // only before the first message
}

TEST(CouplingSequence, TcpExchangeDoesNotStallOnNagleAndDelayedAck) {
  // The test peer, like MBDyn, writes command and payload separately without TCP_NODELAY.
  // Without TCP_QUICKACK on our receives each exchange costs ~40 ms (spec P3).
  const int steps = 200;
  double per_exchange[2] = {0, 0};
  for (int tcp = 0; tcp < 2; ++tcp) {
    auto pair = test::make_pair_setup(two_matrix_nodes(), Coupling::Loose, "latency");
    pair.peer.steps = steps;
    if (tcp) pair.peer.place.tcp_port = 0;
    PeerThread peer(pair.peer);
    if (tcp) pair.session.endpoint = Endpoint::tcp("127.0.0.1", static_cast<std::uint16_t>(peer.port()));
    PeerSession s = PeerSession::open(pair.session);
    ASSERT_TRUE(s.receive().is_kinematics());
    const auto t0 = std::chrono::steady_clock::now();
    for (;;) {
      s.send_loads(Loads(s.config()), true);
      if (!s.receive().is_kinematics()) break;
    }
    per_exchange[tcp] = test::seconds_since(t0) / steps;
    EXPECT_EQ(peer.join().exit_status, 0);
  }
  std::printf("[ latency  ] per exchange: unix %.1f us, tcp %.1f us\n", per_exchange[0] * 1e6, per_exchange[1] * 1e6);
  EXPECT_LT(per_exchange[1], 5e-3);
}
