#include <cstdio>
#include <cstring>
#include <iostream>
#include <stdexcept>
#include <vector>

#include <unistd.h>

#include "exchange_bench.h"
#include "nodal_config.h"
#include "testpeer_wire.h"

namespace dembridge::mbdyn::bench {

std::array<double, 3> BenchShape::position(std::uint32_t k) const {
  if (grid == 0) return {origin[0] + k * spacing[0], origin[1] + k * spacing[1], origin[2] + k * spacing[2]};
  return {origin[0] + (k % grid) * spacing[0], origin[1] + (k / grid) * spacing[1], origin[2]};
}

namespace {

// Command 6 then the kinematics payload of nodes at rest, identity orientation (or none).
std::vector<std::uint8_t> kinematics_message(const BenchShape& shape) {
  testpeer::ElementShape element;
  element.nodes = shape.nodes;
  element.orientation = shape.orientation_none ? testpeer::Orientation::None : testpeer::Orientation::Matrix;
  std::vector<testpeer::NodeState> nodes(shape.nodes);
  for (std::uint32_t k = 0; k < shape.nodes; ++k) {
    const auto x = shape.position(k);
    for (int c = 0; c < 3; ++c) nodes[k].x[c] = x[c];
  }
  std::vector<std::uint8_t> msg{6};
  const auto payload = testpeer::encode_kinematics_payload(element, testpeer::NodeState{}, nodes);
  msg.insert(msg.end(), payload.begin(), payload.end());
  return msg;
}

}  // namespace

int run_fast_peer(const Place& place, const BenchShape& shape, long messages) {
  NodalConfig config;
  config.num_points = shape.nodes;
  config.rotation = shape.rotation();
  try {
    const int fd = listen_and_accept(place, [&](int port) {
      if (port >= 0)
        std::cout << "mbdyn_bench_peer: listening on port " << port << std::endl;
      else
        std::cout << "mbdyn_bench_peer: listening on unix socket " << place.unix_path << std::endl;
    });
    std::uint8_t request[9];
    if (read_full(fd, request, 9) != 9 || request[0] != 7) throw std::runtime_error("no negotiation request");
    std::uint32_t flags, n;
    std::memcpy(&flags, request + 1, 4);
    std::memcpy(&n, request + 5, 4);
    if (flags != config.flags() || n != shape.nodes) {
      const std::uint8_t no = 5;
      write_full(fd, &no, 1);
      throw std::runtime_error("negotiation mismatch: flags " + std::to_string(flags) + " N " + std::to_string(n));
    }
    const std::uint8_t ok = 8;
    write_full(fd, &ok, 1);
    const std::vector<std::uint8_t> kin = kinematics_message(shape);
    std::vector<std::uint8_t> answer(1 + config.loads_payload_bytes());
    for (long m = 0; m < messages; ++m) {
      write_full(fd, kin.data(), kin.size());
      if (read_full(fd, answer.data(), answer.size()) != answer.size() || answer[0] != 6)
        throw std::runtime_error("message " + std::to_string(m) + ": expected command 6 and " +
                                 std::to_string(answer.size() - 1) + " bytes of loads");
    }
    const std::uint8_t end = 5;
    write_full(fd, &end, 1);
    std::uint8_t rest[64];
    while (read_full(fd, rest, sizeof rest) == sizeof rest) {
    }
    ::close(fd);
  } catch (const std::exception& e) {
    std::cout << "mbdyn_bench_peer: error: " << e.what() << std::endl;
    return 1;
  }
  return 0;
}

}  // namespace dembridge::mbdyn::bench
