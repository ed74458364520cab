// Negotiation in both socket roles against the test peer: every configuration succeeds with
// the flags MBDyn expects; every mismatch fails on both sides with a message naming it.
#include <gtest/gtest.h>

#include "protocol_error.h"
#include "test_support.h"

using namespace dembridge::mbdyn;
using dembridge::mbdyn::test::PeerThread;

namespace {

NodalConfig config_of(Rotation r, int bits, std::uint32_t n = 2) {
  NodalConfig c;
  c.num_points = n;
  c.rotation = r;
  c.labels = bits & 1;
  c.accelerations = bits & 2;
  c.reference_node = bits & 4;
  return c;
}

// Runs a 2-step loose coupling with zero loads; returns the steps seen by the library.
int run_zero_load_session(PeerSession& s) {
  int kinematics = 0;
  for (;;) {
    const Received r = s.receive();
    if (!r.is_kinematics()) break;
    ++kinematics;
    s.send_loads(Loads(s.config()), true);
  }
  return kinematics;
}

std::string expect_negotiation_error(PeerSession (*open)(const SessionOptions&), const SessionOptions& o) {
  try {
    open(o);
  } catch (const NegotiationError& e) {
    return e.what();
  }
  ADD_FAILURE() << "expected a NegotiationError";
  return "";
}

}  // namespace

TEST(Negotiation, EveryConfigurationSucceedsOverUnixSocket) {
  for (Rotation r : {Rotation::None, Rotation::OrientationVector, Rotation::OrientationMatrix, Rotation::Euler123})
    for (int bits = 0; bits < 8; ++bits) {
      const NodalConfig c = config_of(r, bits);
      SCOPED_TRACE(c.describe());
      auto pair = test::make_pair_setup(c, Coupling::Loose, "nego");
      pair.peer.steps = 2;
      PeerThread peer(pair.peer);
      PeerSession session = PeerSession::open(pair.session);
      EXPECT_EQ(run_zero_load_session(session), 3);  // t0 + 2 steps
      const auto out = peer.join();
      EXPECT_EQ(out.exit_status, 0) << out.log;
      EXPECT_EQ(out.received_flags, c.flags());
      EXPECT_EQ(out.received_nodes, 2u);
    }
}

TEST(Negotiation, SucceedsOverTcpLoopback) {
  const NodalConfig c = config_of(Rotation::OrientationVector, 0);
  auto pair = test::make_pair_setup(c, Coupling::Loose, "nego-tcp");
  pair.peer.place.tcp_port = 0;
  pair.peer.steps = 2;
  PeerThread peer(pair.peer);
  ASSERT_GT(peer.port(), 0);
  pair.session.endpoint = Endpoint::tcp("127.0.0.1", static_cast<std::uint16_t>(peer.port()));
  PeerSession session = PeerSession::open(pair.session);
  EXPECT_EQ(run_zero_load_session(session), 3);
  const auto out = peer.join();
  EXPECT_EQ(out.exit_status, 0) << out.log;
  EXPECT_EQ(out.received_flags, 0x102u);  // spec §3: loose.mbd
}

TEST(Negotiation, EachMismatchIsRefusedByMbdynAndReported) {
  struct Case {
    const char* name;
    NodalConfig mbdyn, peer;
    const char* mbdyn_log;
  };
  const NodalConfig base = config_of(Rotation::OrientationMatrix, 0);
  NodalConfig more_nodes = base, vector = base, labels = base, acc = base, ref = base;
  more_nodes.num_points = 3;
  vector.rotation = Rotation::OrientationVector;
  labels.labels = true;
  acc.accelerations = true;
  ref.reference_node = true;
  const Case cases[] = {
      {"wrong node count", base, more_nodes, "node count mismatch (local=2, remote=3)"},
      {"orientation", base, vector, "orientation output mismatch (local=512, remote=256)"},
      {"labels", base, labels, "labels mismatch"},
      {"accelerations", base, acc, "accelerations mismatch"},
      {"reference node", base, ref, "reference node mismatch"},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.name);
    auto pair = test::make_pair_setup(c.mbdyn, Coupling::Loose, "nego-fail");
    pair.session.nodal = c.peer;
    PeerThread peer(pair.peer);
    const std::string what = expect_negotiation_error(&PeerSession::open, pair.session);
    EXPECT_NE(what.find("received 5"), std::string::npos) << what;
    EXPECT_NE(what.find(c.peer.describe()), std::string::npos) << what;
    const auto out = peer.join();
    EXPECT_EQ(out.exit_status, 1);
    EXPECT_NE(out.log.find(c.mbdyn_log), std::string::npos) << out.log;
  }
}

TEST(Negotiation, CreateNoRoleReadsMbdynRequestAndRepliesNothing) {
  // MBDyn `create, no`: the library listens, MBDyn connects and sends 07|flags|N|08 (spec §3).
  for (Rotation r : {Rotation::None, Rotation::Euler123})
    for (int bits : {0, 7}) {
      const NodalConfig c = config_of(r, bits, 3);
      SCOPED_TRACE(c.describe());
      auto pair = test::make_pair_setup(c, Coupling::Loose, "nego-no");
      pair.peer.mbdyn_creates_socket = false;
      pair.peer.steps = 2;
      pair.session.role = SocketRole::PeerCreates;
      SocketListener listener(pair.session.endpoint);  // listen before "launching MBDyn"
      PeerThread peer(pair.peer);
      PeerSession session = PeerSession::accept(listener, pair.session);
      // Had the library answered the negotiation, MBDyn would take it as a command: the
      // run would fail on the first load message.
      EXPECT_EQ(run_zero_load_session(session), 3);
      const auto out = peer.join();
      EXPECT_EQ(out.exit_status, 0) << out.log;
    }
}

TEST(Negotiation, CreateNoRoleRejectsWrongNodeCount) {
  NodalConfig mbdyn = config_of(Rotation::OrientationMatrix, 0, 2);
  NodalConfig mine = mbdyn;
  mine.num_points = 3;
  auto pair = test::make_pair_setup(mbdyn, Coupling::Loose, "nego-no-fail");
  pair.peer.mbdyn_creates_socket = false;
  pair.session.role = SocketRole::PeerCreates;
  pair.session.nodal = mine;
  PeerThread peer(pair.peer);
  const std::string what = expect_negotiation_error(&PeerSession::open, pair.session);
  EXPECT_NE(what.find("wrong node count: MBDyn announces N=2, this peer expects 3"), std::string::npos) << what;
  const auto out = peer.join();
  // Our 5 reaches MBDyn as "peer requested end of simulation" (spec §6): exit status 2.
  EXPECT_EQ(out.exit_status, 2) << out.log;
  ASSERT_FALSE(out.answers.empty());
  EXPECT_EQ(out.answers.front(), 5);
}

TEST(Negotiation, CreateNoRoleRejectsOrientationMismatch) {
  NodalConfig mbdyn = config_of(Rotation::OrientationMatrix, 0, 2);
  NodalConfig mine = mbdyn;
  mine.rotation = Rotation::Euler123;
  mine.labels = true;
  auto pair = test::make_pair_setup(mbdyn, Coupling::Loose, "nego-no-rot");
  pair.peer.mbdyn_creates_socket = false;
  pair.session.role = SocketRole::PeerCreates;
  pair.session.nodal = mine;
  PeerThread peer(pair.peer);
  const std::string what = expect_negotiation_error(&PeerSession::open, pair.session);
  EXPECT_NE(what.find("orientation mismatch: MBDyn announces orientation matrix, this peer expects euler 123"),
            std::string::npos) << what;
  EXPECT_NE(what.find("labels mismatch: MBDyn no, this peer yes"), std::string::npos) << what;
  peer.join();
}
