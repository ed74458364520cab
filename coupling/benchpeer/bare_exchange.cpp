#include "bare_exchange.h"

#include <sys/socket.h>
#include <unistd.h>

#include <stdexcept>

#include "negotiation.h"
#include "nodal_config.h"

namespace dembridge::mbdyn::bench {

BareExchange::BareExchange(const Place& place, std::uint32_t nodes, double connect_timeout_s, Rotation rotation) {
  NodalConfig config;
  config.num_points = nodes;
  config.rotation = rotation;
  kin_.resize(1 + config.kinematics_payload_bytes());
  loads_.assign(1 + config.loads_payload_bytes(), 0);
  loads_[0] = 6;
  fd_ = connect_to(place, connect_timeout_s);
  const auto request = negotiation_request_bytes(config);
  write_full(fd_, request.data(), request.size());
  std::uint8_t reply = 0;
  if (read_full(fd_, &reply, 1) != 1 || reply != 8) {
    ::close(fd_);
    throw std::runtime_error("negotiation refused");
  }
  if (!receive()) {
    ::close(fd_);
    throw std::runtime_error("no t0 kinematics");
  }
}

BareExchange::~BareExchange() { finish(); }

bool BareExchange::receive() {
  // One recv, as fix mbdyn's: the 5 at the end comes alone (the peer then waits for our close).
  const long got = ::recv(fd_, kin_.data(), kin_.size(), 0);
  if (got >= 1 && kin_[0] == 5) return !(ended_ = true);
  if (got <= 0 || read_full(fd_, kin_.data() + got, kin_.size() - got) != kin_.size() - got)
    throw std::runtime_error("short kinematics message");
  return true;
}

void BareExchange::send() { write_full(fd_, loads_.data(), loads_.size()); }

void BareExchange::finish() noexcept {
  if (fd_ < 0) return;
  try {  // the peer's 5; if kinematics come instead, we stopped early: closing makes the peer fail
    if (!ended_) receive();
  } catch (...) {
  }
  ::close(fd_);
  fd_ = -1;
}

}  // namespace dembridge::mbdyn::bench
