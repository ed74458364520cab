#include "blocking_socket.h"

#include "socket_address.h"

#include <netinet/tcp.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstring>
#include <stdexcept>
#include <thread>

namespace dembridge::mbdyn::bench {

namespace {

[[noreturn]] void fail(const std::string& what) { throw std::runtime_error(what + ": " + std::strerror(errno)); }

// The address of place (the protocol library's, so both speak the same addresses), in storage big
// enough for either family; returns its length.
socklen_t address_of(const Place& place, sockaddr_storage& storage) {
  std::memset(&storage, 0, sizeof storage);
  if (place.tcp_port >= 0) {
    const sockaddr_in a = inet_address("127.0.0.1", static_cast<std::uint16_t>(place.tcp_port));
    std::memcpy(&storage, &a, sizeof a);
    return sizeof a;
  }
  const sockaddr_un a = unix_address(place.unix_path);
  std::memcpy(&storage, &a, sizeof a);
  return sizeof a;
}

void set_nodelay(const Place& place, int fd) {
  int one = 1;
  if (place.tcp_port >= 0) setsockopt(fd, IPPROTO_TCP, TCP_NODELAY, &one, sizeof one);
}

}  // namespace

int listen_and_accept(const Place& place, const std::function<void(int)>& on_listening) {
  sockaddr_storage addr;
  const socklen_t len = address_of(place, addr);
  const bool tcp = place.tcp_port >= 0;
  const int l = ::socket(tcp ? AF_INET : AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0);
  if (l < 0) fail("socket");
  int one = 1;
  if (tcp) setsockopt(l, SOL_SOCKET, SO_REUSEADDR, &one, sizeof one);
  if (!tcp) ::unlink(place.unix_path.c_str());
  if (::bind(l, reinterpret_cast<sockaddr*>(&addr), len) != 0) fail("bind");
  if (::listen(l, 1) != 0) fail("listen");
  on_listening(tcp ? bound_tcp_port(l) : -1);
  int fd;
  do fd = ::accept(l, nullptr, nullptr);
  while (fd < 0 && errno == EINTR);
  if (fd < 0) fail("accept");
  ::close(l);
  if (!tcp) ::unlink(place.unix_path.c_str());
  set_nodelay(place, fd);
  return fd;
}

int connect_to(const Place& place, double timeout_s) {
  sockaddr_storage addr;
  const socklen_t len = address_of(place, addr);
  const auto until = std::chrono::steady_clock::now() + std::chrono::duration<double>(timeout_s);
  for (;;) {
    const int fd = ::socket(place.tcp_port >= 0 ? AF_INET : AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0);
    if (fd < 0) fail("socket");
    if (::connect(fd, reinterpret_cast<sockaddr*>(&addr), len) == 0) {
      set_nodelay(place, fd);
      return fd;
    }
    const int err = errno;
    ::close(fd);
    if ((err != ENOENT && err != ECONNREFUSED) || std::chrono::steady_clock::now() > until) {
      errno = err;
      fail("connect");
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
}

std::size_t read_full(int fd, void* buffer, std::size_t n) {
  auto* p = static_cast<char*>(buffer);
  std::size_t got = 0;
  while (got < n) {
    const ssize_t rc = ::recv(fd, p + got, n - got, 0);
    if (rc == 0) break;
    if (rc < 0) {
      if (errno == EINTR) continue;
      if (errno == ECONNRESET) break;
      fail("recv");
    }
    got += static_cast<std::size_t>(rc);
  }
  return got;
}

void write_full(int fd, const void* buffer, std::size_t n) {
  const auto* p = static_cast<const char*>(buffer);
  while (n > 0) {
    const ssize_t rc = ::send(fd, p, n, MSG_NOSIGNAL);
    if (rc < 0) {
      if (errno == EINTR) continue;
      fail("send");
    }
    p += rc;
    n -= static_cast<std::size_t>(rc);
  }
}

}  // namespace dembridge::mbdyn::bench
