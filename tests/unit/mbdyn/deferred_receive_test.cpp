// Unix receives that peek a whole message and consume its bytes later (issue 12, P5;
// SocketTransport::defer_consumption): every message still reads as sent; the bytes are consumed
// before our next write, at kDeferredBytes without one, and by anything else that reads, and close().
#include <gtest/gtest.h>
#include <sys/ioctl.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstring>
#include <thread>
#include <vector>

#include "nodal_message.h"
#include "socket_transport.h"

using namespace dembridge::mbdyn;

namespace {

bool has_payload(std::uint8_t cmd) { return cmd == 6; }

// Bytes queued for reading on fd: what the transport has not consumed.
int queued(int fd) {
  int n = -1;
  ::ioctl(fd, FIONREAD, &n);
  return n;
}

// Command 6 and a payload of n bytes that differ from message to message.
std::vector<std::uint8_t> message(std::size_t n, int k) {
  std::vector<std::uint8_t> m(1 + n);
  m[0] = 6;
  for (std::size_t i = 1; i <= n; ++i) m[i] = static_cast<std::uint8_t>(i * 7 + k * 13);
  return m;
}

void send_all(int fd, const std::vector<std::uint8_t>& m) {
  ASSERT_EQ(::send(fd, m.data(), m.size(), 0), static_cast<ssize_t>(m.size()));
}

struct Pair {
  int fds[2] = {-1, -1};
  Pair() { EXPECT_EQ(::socketpair(AF_UNIX, SOCK_STREAM, 0, fds), 0); }
  ~Pair() {
    if (fds[1] >= 0) ::close(fds[1]);
  }
};

// Defers t and reads one 48-byte message through it, which stays queued (49 bytes).
void hold_one_message(SocketTransport& t, const Pair& p) {
  ASSERT_TRUE(t.defer_consumption());
  std::uint8_t cmd = 0, payload[48];
  send_all(p.fds[1], message(48, 1));
  t.read_message(cmd, payload, sizeof payload, has_payload, 5.0, "a command byte", "payload");
  EXPECT_EQ(queued(p.fds[0]), 49);
}

}  // namespace

TEST(DeferredReceive, WholeMessagesArePeekedAndConsumedInBulkWithoutAnswers) {
  Pair p;
  SocketTransport t(p.fds[0], false, "socketpair");
  ASSERT_TRUE(t.defer_consumption());
  constexpr std::size_t n = 16000;  // 5 messages pass kDeferredBytes
  static_assert(5 * (n + 1) >= SocketTransport::kDeferredBytes && 4 * (n + 1) < SocketTransport::kDeferredBytes);
  std::vector<std::uint8_t> payload(n);
  for (int k = 1; k <= 6; ++k) {
    const auto m = message(n, k);
    send_all(p.fds[1], m);
    std::uint8_t cmd = 0;
    const WireSpan span{payload.data(), n};
    t.read_message(cmd, &span, 1, has_payload, 5.0, "a command byte", "payload");
    ASSERT_EQ(cmd, 6);
    ASSERT_EQ(0, std::memcmp(payload.data(), m.data() + 1, n)) << "message " << k;
    // messages 1-4 stay queued (read, not consumed); the 5th passes kDeferredBytes: all consumed
    const int expected = k < 5 ? k * static_cast<int>(n + 1) : (k - 5) * static_cast<int>(n + 1);
    EXPECT_EQ(queued(p.fds[0]), expected) << "after message " << k;
  }
}

TEST(DeferredReceive, PadsPiecesAndLaterReadsKeepTheOrder) {
  Pair p;
  SocketTransport t(p.fds[0], false, "socketpair");
  ASSERT_TRUE(t.defer_consumption());
  constexpr std::size_t n = 48;
  std::uint8_t cmd = 0, payload[n] = {};
  // payload as two arrays with a 4-byte pad between them, as a layout with labels has
  const WireSpan spans[3] = {{payload, 20}, {nullptr, 4}, {payload + 24, 24}};
  const auto first = message(n, 1);
  send_all(p.fds[1], first);
  t.read_message(cmd, spans, 3, has_payload, 5.0, "a command byte", "payload");
  EXPECT_EQ(0, std::memcmp(payload, first.data() + 1, 20));
  EXPECT_EQ(0, std::memcmp(payload + 24, first.data() + 25, 24));
  EXPECT_EQ(queued(p.fds[0]), 49);  // deferred
  // The next message arrives in pieces (MBDyn's separate command and payload writes): what is
  // held back is consumed with it, and the rest is read as before.
  const auto second = message(n, 2);
  std::thread writer([&] {
    for (const auto& piece : {std::pair<int, int>{0, 1}, {1, 20}, {21, 28}}) {
      std::this_thread::sleep_for(std::chrono::milliseconds(30));
      ASSERT_EQ(::send(p.fds[1], second.data() + piece.first, piece.second, 0), piece.second);
    }
  });
  t.read_message(cmd, spans, 3, has_payload, 5.0, "a command byte", "payload");
  writer.join();
  EXPECT_EQ(cmd, 6);
  EXPECT_EQ(0, std::memcmp(payload, second.data() + 1, 20));
  EXPECT_EQ(0, std::memcmp(payload + 24, second.data() + 25, 24));
  EXPECT_EQ(queued(p.fds[0]), 0);
  // A plain read after a deferred message reads the bytes that follow it.
  const auto third = message(n, 3);
  send_all(p.fds[1], third);
  t.read_message(cmd, spans, 3, has_payload, 5.0, "a command byte", "payload");
  EXPECT_EQ(queued(p.fds[0]), 49);
  const std::uint8_t after[3] = {5, 6, 7};
  ASSERT_EQ(::send(p.fds[1], after, 3, 0), 3);
  std::uint8_t got[3] = {};
  t.read_exact(got, 3, 5.0, "three bytes");
  EXPECT_EQ(0, std::memcmp(got, after, 3));
  EXPECT_EQ(queued(p.fds[0]), 0);
}

TEST(DeferredReceive, TheAnswerConsumesFirst) {
  // The held bytes go just before our answer (its wake-up of MBDyn covers theirs); the answer
  // itself arrives whole.
  Pair p;
  SocketTransport t(p.fds[0], false, "socketpair");
  hold_one_message(t, p);
  const std::vector<std::uint8_t> answer = message(24, 2);
  t.write_all(answer.data(), answer.size(), 5.0, "the answer");
  EXPECT_EQ(queued(p.fds[0]), 0);
  std::vector<std::uint8_t> got(answer.size());
  ASSERT_EQ(::recv(p.fds[1], got.data(), got.size(), MSG_WAITALL), static_cast<ssize_t>(got.size()));
  EXPECT_EQ(got, answer);
}

TEST(DeferredReceive, CloseConsumesFirstSoThePeerSeesEndOfStream) {
  // Unread bytes at close make the peer's next read fail with ECONNRESET; MBDyn must see EOF.
  Pair p;
  SocketTransport t(p.fds[0], false, "socketpair");
  hold_one_message(t, p);
  t.close();
  std::uint8_t b;
  EXPECT_EQ(::recv(p.fds[1], &b, 1, 0), 0) << std::strerror(errno);
}

TEST(DeferredReceive, TcpIsNotDeferred) {
  // Only AF_UNIX wakes the writer when its bytes are consumed; TCP reads as before.
  Pair p;  // the flag alone decides
  SocketTransport t(p.fds[0], true, "tcp stand-in");
  EXPECT_FALSE(t.defer_consumption());
}
