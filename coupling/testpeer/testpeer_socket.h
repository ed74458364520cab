// Plain blocking sockets for the test peer, bounded with SO_RCVTIMEO/SO_SNDTIMEO (a different
// mechanism from the protocol library's poll loop, on purpose). Behaves like MBDyn's usesock.cc:
// server with backlog 1, SO_LINGER {on, 0}, no TCP_NODELAY, command and payload sent separately.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>

namespace dembridge::mbdyn::testpeer {

struct SocketPlace {
  std::string unix_path;       // used when tcp_port < 0
  int tcp_port = -1;
  std::string host = "127.0.0.1";
  std::string text() const;
};

class PeerSocket {
 public:
  PeerSocket() = default;
  ~PeerSocket();
  PeerSocket(const PeerSocket&) = delete;
  PeerSocket& operator=(const PeerSocket&) = delete;

  // MBDyn `create, yes`: bind, listen(1) and accept one client within timeout_s. Returns an
  // error text, empty on success. ready_port receives the bound TCP port (useful with port 0).
  std::string serve(const SocketPlace& place, double timeout_s, int* bound_port_out = nullptr);
  // Two steps of serve() so a caller can learn the port before blocking.
  std::string listen_on(const SocketPlace& place, int* bound_port_out);
  std::string accept_client(double timeout_s);
  // MBDyn `create, no`: connect, retrying every 0.1 s on ENOENT/ECONNREFUSED (spec §1).
  std::string connect_to(const SocketPlace& place, double timeout_s);

  void set_io_timeout(double seconds);
  // recv() once; returns bytes read, 0 on EOF, -1 on error/timeout (errno kept).
  long receive_once(void* buf, std::size_t n);
  // recv() until n bytes, EOF or timeout; returns bytes read.
  std::size_t receive_all(void* buf, std::size_t n);
  bool send_bytes(const void* buf, std::size_t n);
  void close_now();  // with SO_LINGER 0: RST on TCP, like MBDyn's final close
  bool is_open() const { return fd_ >= 0; }

 private:
  int fd_ = -1;
  int listen_fd_ = -1;
  std::string unlink_path_;
};

}  // namespace dembridge::mbdyn::testpeer
