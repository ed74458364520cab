#include "socket_transport.h"

#include <fcntl.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <poll.h>
#include <sys/time.h>
#include <sys/socket.h>
#include <sys/uio.h>
#include <sys/un.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <chrono>
#include <cstring>
#include <sstream>
#include <stdexcept>
#include <thread>

#include "deadline.h"
#include "nodal_message.h"
#include "protocol_error.h"
#include "socket_address.h"
#include "stale_socket.h"

namespace dembridge::mbdyn {

namespace {

std::string errno_text(int err) { return std::string(std::strerror(err)) + " (errno " + std::to_string(err) + ")"; }

std::string seconds_text(double s) {
  std::ostringstream o;
  o << s << " s";
  return o.str();
}

std::string progress_text(bool receiving, std::size_t done, std::size_t n) {
  return (receiving ? "received " : "sent ") + std::to_string(done) + " of " + std::to_string(n) + " bytes";
}

void set_tcp_options(int fd) {
  // spec P3: MBDyn does not set TCP_NODELAY; at least our own writes must not wait for ACKs.
  int one = 1;
  setsockopt(fd, IPPROTO_TCP, TCP_NODELAY, &one, sizeof one);
}

// Waits for events on fd; returns false when the deadline expired.
bool wait_for(int fd, short events, const Deadline& deadline) {
  for (;;) {
    pollfd p{fd, events, 0};
    const int rc = ::poll(&p, 1, deadline.poll_timeout_ms());
    if (rc > 0) return true;
    if (rc == 0) {
      if (deadline.expired()) return false;
      continue;
    }
    if (errno == EINTR) continue;
    throw SystemError("poll() failed: " + errno_text(errno));
  }
}

// A message's pieces as the iovecs of one recvmsg/sendmsg, consumed from the front as bytes move
// (a partial transfer goes on where it stopped). Fixed storage: no allocation per message.
class IoList {
 public:
  // n bytes at p; pads (p == nullptr) use the caller's scratch of at most 8 bytes.
  void add(void* p, std::size_t n, void* pad_scratch) {
    if (n == 0) return;
    if (!p && n > 8) throw std::logic_error("IoList: a pad longer than 8 bytes");
    if (count_ == v_.size()) throw std::logic_error("IoList: more pieces than a layout has");
    v_[count_++] = iovec{p ? p : pad_scratch, n};
    bytes_ += n;
  }
  std::size_t bytes() const { return bytes_; }
  void advance(std::size_t n) {
    while (n > 0 && first_ < count_) {
      iovec& f = v_[first_];
      if (n < f.iov_len) {
        f.iov_base = static_cast<std::uint8_t*>(f.iov_base) + n;
        f.iov_len -= n;
        return;
      }
      n -= f.iov_len;
      ++first_;
    }
  }
  msghdr header() {
    msghdr m{};
    m.msg_iov = v_.data() + first_;
    m.msg_iovlen = count_ - first_;
    return m;
  }

 private:
  std::array<iovec, 24> v_{};  // a layout has at most 17 pieces (spec §4: all optional blocks)
  std::size_t first_ = 0, count_ = 0, bytes_ = 0;
};

bool is_retryable_connect_error(int err) {
  // The socket does not exist yet, nobody listens yet, or MBDyn's backlog of 1 is full.
  return err == ENOENT || err == ECONNREFUSED || err == EAGAIN || err == ECONNRESET;
}

}  // namespace

Endpoint Endpoint::unix_path(const std::string& path) {
  Endpoint e;
  e.kind = Kind::Unix;
  e.path = path;
  return e;
}

Endpoint Endpoint::tcp(const std::string& host, std::uint16_t port) {
  Endpoint e;
  e.kind = Kind::Tcp;
  e.host = host;
  e.port = port;
  return e;
}

std::string Endpoint::describe() const {
  if (kind == Kind::Unix) return "unix socket " + path;
  return "tcp " + host + ":" + std::to_string(port);
}

SocketTransport::SocketTransport(int fd, bool tcp, std::string description)
    : fd_(fd), tcp_(tcp), description_(std::move(description)) {
  // A blocking descriptor, so that a message's first recv can wait in the kernel (bounded by
  // SO_RCVTIMEO, see read_message); every other call passes MSG_DONTWAIT and waits in poll().
  const int flags = fd_ >= 0 ? ::fcntl(fd_, F_GETFL) : -1;
  if (flags >= 0 && (flags & O_NONBLOCK)) ::fcntl(fd_, F_SETFL, flags & ~O_NONBLOCK);
}

SocketTransport::SocketTransport(SocketTransport&& o) noexcept
    : fd_(o.fd_),
      tcp_(o.tcp_),
      description_(std::move(o.description_)),
      recv_timeout_s_(o.recv_timeout_s_),
      deferring_(o.deferring_),
      deferred_(o.deferred_),
      drain_(std::move(o.drain_)) {
  o.fd_ = -1;
  o.deferred_ = 0;
}

SocketTransport& SocketTransport::operator=(SocketTransport&& o) noexcept {
  if (this != &o) {
    close();
    fd_ = o.fd_;
    tcp_ = o.tcp_;
    description_ = std::move(o.description_);
    recv_timeout_s_ = o.recv_timeout_s_;
    deferring_ = o.deferring_;
    deferred_ = o.deferred_;
    drain_ = std::move(o.drain_);
    o.fd_ = -1;
    o.deferred_ = 0;
  }
  return *this;
}

SocketTransport::~SocketTransport() { close(); }

void SocketTransport::close() noexcept {
  // Unread bytes at close would make the peer's next read fail with ECONNRESET instead of EOF.
  try {
    if (fd_ >= 0) consume_deferred();
  } catch (...) {
  }
  if (fd_ >= 0) ::close(fd_);
  fd_ = -1;
  deferred_ = 0;
}

bool SocketTransport::defer_consumption() {
  if (fd_ < 0 || tcp_) return false;
  int zero = 0;  // peeks start at offset 0 and move on by what they read
  deferring_ = ::setsockopt(fd_, SOL_SOCKET, SO_PEEK_OFF, &zero, sizeof zero) == 0;
  // room for kDeferredBytes and one more message of up to as much: one recv per consumption;
  // allocated here, before the run, and never zeroed
  if (deferring_ && !drain_) drain_.reset(new std::uint8_t[2 * kDeferredBytes]);
  return deferring_;
}

void SocketTransport::consume_deferred() {
  while (deferred_ > 0) {
    const ssize_t rc = ::recv(fd_, drain_.get(), std::min(deferred_, 2 * kDeferredBytes), MSG_DONTWAIT);
    if (rc > 0) {
      deferred_ -= static_cast<std::size_t>(rc);
      continue;
    }
    if (rc < 0 && errno == EINTR) continue;
    const int err = rc < 0 ? errno : 0;
    deferred_ = 0;  // the peeked bytes were queued: only a reset takes them away
    throw SystemError("recv() of already received bytes from " + description_ + ": " +
                      (rc == 0 ? std::string("end of stream") : errno_text(err)));
  }
}

SocketTransport SocketTransport::connect(const Endpoint& endpoint, double timeout_s) {
  const Deadline deadline(timeout_s);
  const bool tcp = endpoint.kind == Endpoint::Kind::Tcp;
  sockaddr_un ua{};
  sockaddr_in ia{};
  if (tcp)
    ia = inet_address(endpoint.host, endpoint.port);
  else
    ua = unix_address(endpoint.path);
  const sockaddr* addr = tcp ? reinterpret_cast<const sockaddr*>(&ia) : reinterpret_cast<const sockaddr*>(&ua);
  const socklen_t len = tcp ? sizeof ia : sizeof ua;

  int last_error = 0;
  for (;;) {
    const int fd = ::socket(tcp ? AF_INET : AF_UNIX, SOCK_STREAM | SOCK_NONBLOCK | SOCK_CLOEXEC, 0);
    if (fd < 0) throw SystemError("socket() for " + endpoint.describe() + ": " + errno_text(errno));
    int err = 0;
    if (::connect(fd, addr, len) != 0) {
      err = errno;
      if (err == EINPROGRESS || err == EINTR) {
        if (!wait_for(fd, POLLOUT, deadline)) {
          ::close(fd);
          throw TimeoutError("connecting to MBDyn on " + endpoint.describe() +
                             ": expected the connection within " + seconds_text(timeout_s) +
                             ", still in progress");
        }
        socklen_t sl = sizeof err;
        getsockopt(fd, SOL_SOCKET, SO_ERROR, &err, &sl);
      }
    }
    if (err == 0) {
      if (tcp) set_tcp_options(fd);
      return SocketTransport(fd, tcp, endpoint.describe());
    }
    ::close(fd);
    if (!is_retryable_connect_error(err))
      throw SystemError("connecting to MBDyn on " + endpoint.describe() + ": " + errno_text(err));
    last_error = err;
    // libmbc and MBDyn retry every 100 ms (spec §1).
    const int left = deadline.poll_timeout_ms();
    if (left == 0)
      throw TimeoutError("connecting to MBDyn on " + endpoint.describe() +
                         ": expected MBDyn to accept within " + seconds_text(timeout_s) +
                         ", last attempt failed with " + errno_text(last_error) +
                         " (is MBDyn running with `socket, create, yes`?)");
    std::this_thread::sleep_for(std::chrono::milliseconds(left < 0 ? 100 : std::min(left, 100)));
  }
}

void SocketTransport::quick_ack() {
  // spec P3: the flag is not sticky; without it MBDyn's split writes stall ~40 ms on Nagle.
  if (!tcp_) return;
  int one = 1;
  setsockopt(fd_, IPPROTO_TCP, TCP_QUICKACK, &one, sizeof one);
}

void SocketTransport::wait_ready(short events, const Deadline& deadline, double timeout_s, const std::string& what,
                                 std::size_t done, std::size_t n) {
  if (wait_for(fd_, events, deadline)) return;
  const bool in = events == POLLIN;
  throw TimeoutError("timed out after " + seconds_text(timeout_s) + (in ? " waiting for " : " sending ") + what +
                     (in ? " from" : " to") + " MBDyn (" + description_ + "): " + progress_text(in, done, n));
}

void SocketTransport::io_failed(long rc, int err, short events, const Deadline& deadline, double timeout_s,
                                const std::string& what, std::size_t done, std::size_t n) {
  const bool in = events == POLLIN;
  if (in && rc == 0)
    throw PeerClosedError("MBDyn closed the connection (" + description_ + ") while " + what +
                          " was expected: " + progress_text(in, done, n));
  if (err == EINTR) return;
  if (err == EAGAIN || err == EWOULDBLOCK) return wait_ready(events, deadline, timeout_s, what, done, n);
  if (in && err == ECONNRESET)
    throw PeerClosedError("MBDyn reset the connection (" + description_ + ") while " + what +
                          " was expected: " + progress_text(in, done, n));
  if (!in && (err == EPIPE || err == ECONNRESET))
    throw PeerClosedError("MBDyn closed the connection (" + description_ + ") while sending " + what + ": " +
                          progress_text(in, done, n));
  throw SystemError((in ? "recv() of " : "send() of ") + what + (in ? " from " : " to ") + description_ + ": " +
                    errno_text(err));
}

void SocketTransport::read_exact(void* buffer, std::size_t n, double timeout_s, const std::string& what) {
  if (fd_ < 0) throw PeerClosedError("reading " + what + ": the connection to MBDyn is closed");
  consume_deferred();  // these bytes come after them
  const Deadline deadline(timeout_s);
  auto* p = static_cast<std::uint8_t*>(buffer);
  std::size_t got = 0;
  while (got < n) {
    quick_ack();
    const ssize_t rc = ::recv(fd_, p + got, n - got, MSG_DONTWAIT);
    if (rc > 0)
      got += static_cast<std::size_t>(rc);
    else
      io_failed(rc, errno, POLLIN, deadline, timeout_s, what, got, n);
  }
}

bool SocketTransport::set_receive_timeout(double timeout_s) {
  if (timeout_s == 0.0) return false;  // SO_RCVTIMEO 0 would mean "forever"
  if (timeout_s == recv_timeout_s_) return true;
  timeval tv{0, 0};  // < 0: wait forever (0 in SO_RCVTIMEO)
  if (timeout_s > 0.0) {
    const double s = std::min(timeout_s, 1e9);
    tv.tv_sec = static_cast<time_t>(s);
    tv.tv_usec = static_cast<suseconds_t>(1e6 * (s - static_cast<double>(tv.tv_sec)));
    if (tv.tv_sec == 0 && tv.tv_usec == 0) tv.tv_usec = 1;
  }
  if (::setsockopt(fd_, SOL_SOCKET, SO_RCVTIMEO, &tv, sizeof tv) != 0) return false;
  recv_timeout_s_ = timeout_s;
  return true;
}

void SocketTransport::read_message(std::uint8_t& cmd, void* payload, std::size_t n,
                                   bool (*payload_follows)(std::uint8_t), double timeout_s,
                                   const std::string& what_command, const std::string& what_payload) {
  const WireSpan whole{payload, n};
  read_message(cmd, &whole, 1, payload_follows, timeout_s, what_command, what_payload);
}

void SocketTransport::read_message(std::uint8_t& cmd, const WireSpan* payload, std::size_t count,
                                   bool (*payload_follows)(std::uint8_t), double timeout_s,
                                   const std::string& what_command, const std::string& what_payload) {
  if (fd_ < 0) throw PeerClosedError("reading " + what_command + ": the connection to MBDyn is closed");
  const Deadline deadline(timeout_s);
  std::uint8_t pad[8];  // the wire's pads land here (ignored on receipt, spec §2)
  IoList io;
  io.add(&cmd, 1, pad);
  for (std::size_t i = 0; i < count; ++i) io.add(payload[i].data, payload[i].size, pad);
  const std::size_t n = io.bytes() - 1;  // payload bytes
  // Fast path, one system call: a recvmsg for command and payload that blocks in the kernel, bounded
  // by SO_RCVTIMEO = the whole message's timeout (spec P4), instead of poll + recv (+ TCP_QUICKACK).
  // MBDyn's message usually arrives whole (or is already there). Without a quick ack first, a split
  // write (MBDyn's command byte, its payload held back by Nagle until our ACK, spec P3) returns the
  // byte at once, and the loop below acks before it waits for the rest.
  msghdr m = io.header();
  ssize_t rc;
  std::size_t got = 0;  // payload bytes, once the command byte is in
  bool have_cmd = false;
  if (deferring_) {
    // Unix: a message already here whole is only peeked (see defer_consumption).
    rc = ::recvmsg(fd_, &m, MSG_PEEK | MSG_DONTWAIT);
    if (rc > 0) {
      have_cmd = true;
      got = static_cast<std::size_t>(rc) - 1;
      io.advance(static_cast<std::size_t>(rc));
      if (!payload_follows(cmd) || got == n) {
        deferred_ += static_cast<std::size_t>(rc);
        if (deferred_ >= kDeferredBytes) consume_deferred();
        return;
      }
      deferred_ += static_cast<std::size_t>(rc);  // in the arrays already: consumed below with the rest
    } else if (rc == 0 || (errno != EAGAIN && errno != EWOULDBLOCK && errno != EINTR)) {
      io_failed(rc, errno, POLLIN, deadline, timeout_s, what_command, 0, 1);  // throws
    }
    // Not all here: MBDyn is still writing or computing, not asleep in recv. Consuming now wakes
    // nobody for nothing; the rest is read (and consumed) as below.
    consume_deferred();
  }
  if (!have_cmd) {
    rc = ::recvmsg(fd_, &m, set_receive_timeout(timeout_s) ? 0 : MSG_DONTWAIT);
    if (rc > 0) {
      have_cmd = true;
      got = static_cast<std::size_t>(rc) - 1;
      if (!payload_follows(cmd) || got == n) return;
      io.advance(static_cast<std::size_t>(rc));
    } else if (rc == 0 || (errno != EAGAIN && errno != EWOULDBLOCK && errno != EINTR)) {
      io_failed(rc, errno, POLLIN, deadline, timeout_s, what_command, 0, 1);  // throws
    }
  }
  while (!have_cmd || got < n) {
    quick_ack();
    if (have_cmd)
      wait_ready(POLLIN, deadline, timeout_s, what_payload, got, n);
    else
      wait_ready(POLLIN, deadline, timeout_s, what_command, 0, 1);
    m = io.header();
    rc = ::recvmsg(fd_, &m, MSG_DONTWAIT);
    if (rc > 0) {
      io.advance(static_cast<std::size_t>(rc));
      if (have_cmd) {
        got += static_cast<std::size_t>(rc);
        continue;
      }
      have_cmd = true;
      got = static_cast<std::size_t>(rc) - 1;
      if (!payload_follows(cmd)) return;
      continue;
    }
    const int err = errno;
    if (have_cmd)
      io_failed(rc, err, POLLIN, deadline, timeout_s, what_payload, got, n);
    else
      io_failed(rc, err, POLLIN, deadline, timeout_s, what_command, 0, 1);
  }
}

void SocketTransport::write_all(const void* buffer, std::size_t n, double timeout_s, const std::string& what) {
  if (fd_ < 0) throw PeerClosedError("writing " + what + ": the connection to MBDyn is closed");
  // Consumed here, just before the answer: the wake-up this gives MBDyn merges with the one our
  // send gives it anyway, and the send's buffers come from the ones just freed.
  if (deferred_ > 0) consume_deferred();
  const Deadline deadline(timeout_s);
  const auto* p = static_cast<const std::uint8_t*>(buffer);
  std::size_t sent = 0;
  while (sent < n) {
    // MSG_NOSIGNAL: a dead MBDyn must give an error, not kill LAMMPS with SIGPIPE.
    const ssize_t rc = ::send(fd_, p + sent, n - sent, MSG_NOSIGNAL | MSG_DONTWAIT);
    if (rc >= 0) {
      sent += static_cast<std::size_t>(rc);
      continue;
    }
    io_failed(rc, errno, POLLOUT, deadline, timeout_s, what, sent, n);
  }
}

bool SocketTransport::try_write_byte(std::uint8_t byte, double timeout_s) noexcept {
  try {
    write_all(&byte, 1, timeout_s, "command " + std::to_string(byte));
    return true;
  } catch (...) {
    return false;
  }
}

SocketListener::SocketListener(const Endpoint& endpoint) : endpoint_(endpoint) {
  const bool tcp = endpoint.kind == Endpoint::Kind::Tcp;
  fd_ = ::socket(tcp ? AF_INET : AF_UNIX, SOCK_STREAM | SOCK_NONBLOCK | SOCK_CLOEXEC, 0);
  if (fd_ < 0) throw SystemError("socket() for " + endpoint.describe() + ": " + errno_text(errno));
  int rc;
  if (tcp) {
    int one = 1;
    setsockopt(fd_, SOL_SOCKET, SO_REUSEADDR, &one, sizeof one);
    const sockaddr_in addr = inet_address(endpoint.host, endpoint.port);
    rc = ::bind(fd_, reinterpret_cast<const sockaddr*>(&addr), sizeof addr);
  } else {
    const sockaddr_un addr = unix_address(endpoint.path);
    remove_stale_unix_socket(endpoint.path);  // a crashed run's socket; never a user's file
    rc = ::bind(fd_, reinterpret_cast<const sockaddr*>(&addr), sizeof addr);
  }
  if (rc != 0 || ::listen(fd_, 1) != 0) {
    const int err = errno;
    ::close(fd_);
    fd_ = -1;
    throw SystemError("cannot listen on " + endpoint.describe() + ": " + errno_text(err));
  }
  if (tcp) bound_port_ = bound_tcp_port(fd_);
}

SocketListener::SocketListener(SocketListener&& o) noexcept
    : endpoint_(std::move(o.endpoint_)), fd_(o.fd_), bound_port_(o.bound_port_) {
  o.fd_ = -1;
}

SocketListener::~SocketListener() { close(); }

void SocketListener::close() noexcept {
  if (fd_ < 0) return;
  ::close(fd_);
  fd_ = -1;
  if (endpoint_.kind == Endpoint::Kind::Unix) ::unlink(endpoint_.path.c_str());
}

SocketTransport SocketListener::accept(double timeout_s) {
  if (fd_ < 0) throw SystemError("accept on " + endpoint_.describe() + ": the listener is closed");
  const Deadline deadline(timeout_s);
  for (;;) {
    const int fd = ::accept4(fd_, nullptr, nullptr, SOCK_NONBLOCK | SOCK_CLOEXEC);
    if (fd >= 0) {
      const bool tcp = endpoint_.kind == Endpoint::Kind::Tcp;
      if (tcp) set_tcp_options(fd);
      std::string description = endpoint_.describe();
      if (tcp) description = "tcp " + endpoint_.host + ":" + std::to_string(bound_port_);
      close();
      return SocketTransport(fd, tcp, description);
    }
    const int err = errno;
    if (err == EINTR || err == ECONNABORTED) continue;
    if (err != EAGAIN && err != EWOULDBLOCK)
      throw SystemError("accept() on " + endpoint_.describe() + ": " + errno_text(err));
    if (!wait_for(fd_, POLLIN, deadline))
      throw TimeoutError("waiting on " + endpoint_.describe() + ": expected MBDyn (`socket, create, no`) to connect within " +
                         seconds_text(timeout_s) + ", nobody connected");
  }
}

}  // namespace dembridge::mbdyn
