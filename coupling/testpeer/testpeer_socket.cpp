#include "testpeer_socket.h"

#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <sys/time.h>
#include <sys/un.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstring>
#include <thread>

namespace dembridge::mbdyn::testpeer {

namespace {

// A zero timeval means "block forever" to SO_RCVTIMEO/SO_SNDTIMEO: MBDyn's own behaviour,
// selected with a timeout <= 0.
timeval to_timeval(double s) {
  timeval tv{};
  if (s <= 0) return tv;
  if (s < 1e-6) s = 1e-6;
  tv.tv_sec = static_cast<time_t>(s);
  tv.tv_usec = static_cast<suseconds_t>((s - static_cast<double>(tv.tv_sec)) * 1e6);
  return tv;
}

std::string err_text(const char* what) { return std::string(what) + ": " + std::strerror(errno); }

}  // namespace

std::string SocketPlace::text() const {
  return tcp_port >= 0 ? host + ":" + std::to_string(tcp_port) : unix_path;
}

PeerSocket::~PeerSocket() {
  close_now();
  if (listen_fd_ >= 0) ::close(listen_fd_);
  if (!unlink_path_.empty()) ::unlink(unlink_path_.c_str());
}

std::string PeerSocket::listen_on(const SocketPlace& place, int* bound_port_out) {
  if (place.tcp_port >= 0) {
    listen_fd_ = ::socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);
    if (listen_fd_ < 0) return err_text("socket");
    int one = 1;
    setsockopt(listen_fd_, SOL_SOCKET, SO_REUSEADDR, &one, sizeof one);
    sockaddr_in a{};
    a.sin_family = AF_INET;
    a.sin_port = htons(static_cast<std::uint16_t>(place.tcp_port));
    if (inet_pton(AF_INET, place.host.c_str(), &a.sin_addr) != 1) return "bad host " + place.host;
    if (::bind(listen_fd_, reinterpret_cast<sockaddr*>(&a), sizeof a) != 0) return err_text("bind() failed");
    socklen_t len = sizeof a;
    getsockname(listen_fd_, reinterpret_cast<sockaddr*>(&a), &len);
    if (bound_port_out) *bound_port_out = ntohs(a.sin_port);
  } else {
    listen_fd_ = ::socket(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0);
    if (listen_fd_ < 0) return err_text("socket");
    sockaddr_un a{};
    a.sun_family = AF_UNIX;
    if (place.unix_path.size() >= sizeof a.sun_path) return "path too long";
    std::strcpy(a.sun_path, place.unix_path.c_str());
    // Real MBDyn refuses a stale path (spec §1); the test peer removes it to keep tests simple.
    ::unlink(place.unix_path.c_str());
    if (::bind(listen_fd_, reinterpret_cast<sockaddr*>(&a), sizeof a) != 0)
      return "UseLocalSocket(" + place.unix_path + "): " + err_text("bind() failed");
    unlink_path_ = place.unix_path;
  }
  if (::listen(listen_fd_, 1) != 0) return err_text("listen");
  return "";
}

std::string PeerSocket::accept_client(double timeout_s) {
  // Linux honours SO_RCVTIMEO on accept(); this is the `select timeout` of MBDyn.
  const timeval tv = to_timeval(timeout_s);
  setsockopt(listen_fd_, SOL_SOCKET, SO_RCVTIMEO, &tv, sizeof tv);
  for (;;) {
    fd_ = ::accept(listen_fd_, nullptr, nullptr);
    if (fd_ >= 0) break;
    if (errno == EINTR) continue;
    if (errno == EAGAIN || errno == EWOULDBLOCK) return "no peer connected within the accept timeout";
    return err_text("accept");
  }
  ::close(listen_fd_);
  listen_fd_ = -1;
  linger lg{1, 0};  // MBDyn: SO_LINGER {on, 0} after connecting (spec §1)
  setsockopt(fd_, SOL_SOCKET, SO_LINGER, &lg, sizeof lg);
  return "";
}

std::string PeerSocket::serve(const SocketPlace& place, double timeout_s, int* bound_port_out) {
  std::string e = listen_on(place, bound_port_out);
  if (!e.empty()) return e;
  return accept_client(timeout_s);
}

std::string PeerSocket::connect_to(const SocketPlace& place, double timeout_s) {
  // MBDyn as a client retries for at most 60 s (spec §1); that is also the "no timeout" case.
  if (timeout_s <= 0) timeout_s = 60.0;
  const auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(timeout_s);
  for (;;) {
    int rc;
    if (place.tcp_port >= 0) {
      fd_ = ::socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);
      sockaddr_in a{};
      a.sin_family = AF_INET;
      a.sin_port = htons(static_cast<std::uint16_t>(place.tcp_port));
      inet_pton(AF_INET, place.host.c_str(), &a.sin_addr);
      rc = ::connect(fd_, reinterpret_cast<sockaddr*>(&a), sizeof a);
    } else {
      fd_ = ::socket(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0);
      sockaddr_un a{};
      a.sun_family = AF_UNIX;
      std::strncpy(a.sun_path, place.unix_path.c_str(), sizeof a.sun_path - 1);
      rc = ::connect(fd_, reinterpret_cast<sockaddr*>(&a), sizeof a);
    }
    if (rc == 0) break;
    const int err = errno;
    ::close(fd_);
    fd_ = -1;
    if (err != ENOENT && err != ECONNREFUSED) {
      errno = err;
      return err_text("connect");
    }
    if (std::chrono::steady_clock::now() >= end) return "could not connect to " + place.text() + " within the timeout";
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
  linger lg{1, 0};
  setsockopt(fd_, SOL_SOCKET, SO_LINGER, &lg, sizeof lg);
  return "";
}

void PeerSocket::set_io_timeout(double seconds) {
  if (fd_ < 0) return;
  const timeval tv = to_timeval(seconds);
  setsockopt(fd_, SOL_SOCKET, SO_RCVTIMEO, &tv, sizeof tv);
  setsockopt(fd_, SOL_SOCKET, SO_SNDTIMEO, &tv, sizeof tv);
}

long PeerSocket::receive_once(void* buf, std::size_t n) {
  for (;;) {
    const ssize_t rc = ::recv(fd_, buf, n, 0);
    if (rc < 0 && errno == EINTR) continue;
    return static_cast<long>(rc);
  }
}

std::size_t PeerSocket::receive_all(void* buf, std::size_t n) {
  std::size_t got = 0;
  while (got < n) {
    const long rc = receive_once(static_cast<char*>(buf) + got, n - got);
    if (rc <= 0) break;
    got += static_cast<std::size_t>(rc);
  }
  return got;
}

bool PeerSocket::send_bytes(const void* buf, std::size_t n) {
  std::size_t sent = 0;
  while (sent < n) {
    const ssize_t rc = ::send(fd_, static_cast<const char*>(buf) + sent, n - sent, MSG_NOSIGNAL);
    if (rc < 0 && errno == EINTR) continue;
    if (rc <= 0) return false;
    sent += static_cast<std::size_t>(rc);
  }
  return true;
}

void PeerSocket::close_now() {
  if (fd_ >= 0) ::close(fd_);
  fd_ = -1;
}

}  // namespace dembridge::mbdyn::testpeer
