// Socket addresses of an MBDyn endpoint, written once for the protocol library and the bench peer
// (coupling/benchpeer/): a Unix path checked against sun_path, an IPv4 host by number or name.
#pragma once

#include <netinet/in.h>
#include <sys/un.h>

#include <cstdint>
#include <string>

namespace dembridge::mbdyn {

// Throws SystemError when path is empty or does not fit sun_path.
sockaddr_un unix_address(const std::string& path);
// host as dotted quad, else resolved (IPv4); throws SystemError when it cannot be resolved.
sockaddr_in inet_address(const std::string& host, std::uint16_t port);
// The TCP port a listening socket is bound to (useful after binding port 0).
std::uint16_t bound_tcp_port(int fd);

}  // namespace dembridge::mbdyn
