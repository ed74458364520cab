// Plain blocking stream sockets for the exchange benchmark's peer and bare client: no poll, no
// timeouts, TCP_NODELAY on both ends, so the socket floor is all they measure.
#pragma once

#include <cstddef>
#include <functional>
#include <string>

namespace dembridge::mbdyn::bench {

struct Place {
  std::string unix_path;  // used when tcp_port < 0
  int tcp_port = -1;      // 127.0.0.1
};

// Listens (backlog 1), calls on_listening(bound TCP port or -1), accepts one client. Returns its
// fd; throws std::runtime_error.
int listen_and_accept(const Place& place, const std::function<void(int)>& on_listening);
// Connects, retrying every 10 ms for up to timeout_s while nobody listens yet. Throws.
int connect_to(const Place& place, double timeout_s);

// Reads until n bytes or EOF; returns the bytes read (fewer only at EOF). Throws on errors.
std::size_t read_full(int fd, void* buffer, std::size_t n);
// One send() for the whole buffer unless the kernel takes less. Throws on errors.
void write_full(int fd, const void* buffer, std::size_t n);

}  // namespace dembridge::mbdyn::bench
