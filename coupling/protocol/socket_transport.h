// Byte transport to MBDyn over a stream socket (spec §1): AF_UNIX path or TCP. Every blocking
// call has a deadline (spec P4): a message's first recv waits in the kernel under SO_RCVTIMEO,
// everything else in poll(); reads are exact-length (P1); a message goes out in one send() (P2);
// TCP gets TCP_NODELAY, and TCP_QUICKACK before every wait for the rest of a message (P3).
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>

namespace dembridge::mbdyn {

class Deadline;
struct WireSpan;

// Where the MBDyn socket lives: `path, "<file>"` or `port, <n> [, host, "<h>"]`.
struct Endpoint {
  enum class Kind { Unix, Tcp };
  Kind kind = Kind::Unix;
  std::string path;               // Unix
  std::string host = "127.0.0.1";  // Tcp; MBDyn's default host (spec §1)
  std::uint16_t port = 0;         // Tcp

  static Endpoint unix_path(const std::string& path);
  static Endpoint tcp(const std::string& host, std::uint16_t port);
  std::string describe() const;  // "unix socket /x/mbdyn.sock" or "tcp 127.0.0.1:9011"
};

class SocketTransport {
 public:
  SocketTransport() = default;
  SocketTransport(int fd, bool tcp, std::string description);
  SocketTransport(SocketTransport&& o) noexcept;
  SocketTransport& operator=(SocketTransport&& o) noexcept;
  SocketTransport(const SocketTransport&) = delete;
  SocketTransport& operator=(const SocketTransport&) = delete;
  ~SocketTransport();

  // MBDyn `create, yes`: connect, retrying every 100 ms while the socket does not exist yet or
  // refuses (ENOENT/ECONNREFUSED), until timeout_s (spec §1, P11). Throws TimeoutError.
  static SocketTransport connect(const Endpoint& endpoint, double timeout_s);

  // Reads exactly n bytes. what names the expected data in error messages
  // ("kinematics payload"); throws TimeoutError or PeerClosedError stating bytes received.
  void read_exact(void* buffer, std::size_t n, double timeout_s, const std::string& what);
  // Reads one message: its command byte into cmd and, when payload_follows(cmd), exactly n more
  // bytes into payload. A whole message costs one system call: a recvmsg of both that blocks
  // until data arrives (SO_RCVTIMEO = timeout_s). Only a partial message (MBDyn's split writes on
  // TCP) goes on with TCP_QUICKACK, poll() and recv. A command without payload ends the read: bytes
  // after it are dropped (MBDyn sends nothing after 5, and any other such byte is a protocol
  // error). Errors as read_exact, naming what_command or what_payload.
  void read_message(std::uint8_t& cmd, void* payload, std::size_t n, bool (*payload_follows)(std::uint8_t),
                    double timeout_s, const std::string& what_command, const std::string& what_payload);
  // The same with the payload scattered over count pieces (nullptr pieces: pads, dropped). (For
  // MBDyn's messages a scatter over six arrays measured slower than one buffer plus the copies.)
  void read_message(std::uint8_t& cmd, const WireSpan* payload, std::size_t count,
                    bool (*payload_follows)(std::uint8_t), double timeout_s, const std::string& what_command,
                    const std::string& what_payload);
  // Writes n bytes with a single send() when the kernel takes them (always for small messages);
  // loops only on a partial send. Throws TimeoutError or PeerClosedError.
  void write_all(const void* buffer, std::size_t n, double timeout_s, const std::string& what);
  // Unix sockets (issue 12, P5): read_message then reads a whole message with MSG_PEEK and
  // consumes the bytes later: in the next write (just before our answer), as soon as a message is
  // not all there yet, or at kDeferredBytes (a peer we never answer). Consuming the peer's bytes
  // frees its send buffer, and Linux then wakes the peer if it sleeps in recv (AF_UNIX write-space
  // wake-up, unconditional for a blocked reader). MBDyn sleeps in recv waiting for our answer
  // whenever its message is already here, so every receive woke it once for nothing (a cross-core
  // IPI, or a switch to it on LAMMPS's core). Consumed just before the answer, that wake-up merges
  // with the one the answer gives anyway; while MBDyn is still writing or computing it wakes
  // nobody. Every other read and close() consume the deferred bytes first. False (nothing
  // changes) for TCP, whose receive wakes nobody, or when the kernel lacks SO_PEEK_OFF.
  bool defer_consumption();
  static constexpr std::size_t kDeferredBytes = 64 * 1024;
  // Best effort for clean aborts: tries to write one byte within timeout_s, never throws.
  bool try_write_byte(std::uint8_t byte, double timeout_s) noexcept;

  void close() noexcept;
  bool is_open() const { return fd_ >= 0; }
  bool is_tcp() const { return tcp_; }
  int fd() const { return fd_; }
  const std::string& description() const { return description_; }

 private:
  // Waits in poll() for events (POLLIN: reading, POLLOUT: writing) on a transfer of n bytes of
  // what, done so far; throws TimeoutError at the deadline. The wording of every transfer error
  // is here and in io_failed, once for reads and writes.
  void wait_ready(short events, const Deadline& deadline, double timeout_s, const std::string& what, std::size_t done,
                  std::size_t n);
  // After a recv (events POLLIN) or send (POLLOUT) that returned rc (errno err): returns to retry
  // (EINTR, or the socket ready again within the deadline); throws otherwise.
  void io_failed(long rc, int err, short events, const Deadline& deadline, double timeout_s, const std::string& what,
                 std::size_t done, std::size_t n);
  void quick_ack();
  // Sets SO_RCVTIMEO to timeout_s (< 0: forever) unless it is set already; false when a blocking
  // recv cannot honour the timeout (0 s), so the caller must not block.
  bool set_receive_timeout(double timeout_s);
  // Consumes the deferred bytes (they are queued: recv without waiting); throws on a socket error.
  void consume_deferred();
  int fd_ = -1;
  bool tcp_ = false;
  std::string description_;
  double recv_timeout_s_ = 0.0;  // SO_RCVTIMEO as last set; 0: not set
  bool deferring_ = false;            // defer_consumption() is on
  std::size_t deferred_ = 0;          // bytes read with MSG_PEEK, not consumed yet
  std::unique_ptr<std::uint8_t[]> drain_;  // where consumed bytes go: 2 kDeferredBytes, not zeroed
};

// MBDyn `create, no`: the peer listens and MBDyn connects while it parses its input (spec §1).
// Listening starts in the constructor so MBDyn can be launched afterwards; a Unix path is
// unlinked before bind (stale file) and after close.
class SocketListener {
 public:
  explicit SocketListener(const Endpoint& endpoint);
  SocketListener(SocketListener&& o) noexcept;
  SocketListener(const SocketListener&) = delete;
  SocketListener& operator=(const SocketListener&) = delete;
  ~SocketListener();

  // Waits for one connection up to timeout_s (TimeoutError), then stops listening.
  SocketTransport accept(double timeout_s);
  std::uint16_t bound_port() const { return bound_port_; }  // TCP, useful with port 0
  void close() noexcept;

 private:
  Endpoint endpoint_;
  int fd_ = -1;
  std::uint16_t bound_port_ = 0;
};

}  // namespace dembridge::mbdyn
