#include <sys/resource.h>
#include <sys/socket.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <stdexcept>
#include <vector>

#include "exchange_bench.h"
#include "negotiation.h"
#include "nodal_config.h"

namespace dembridge::mbdyn::bench {

namespace {

double cpu_seconds() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return static_cast<double>(u.ru_utime.tv_sec + u.ru_stime.tv_sec) +
         1e-6 * static_cast<double>(u.ru_utime.tv_usec + u.ru_stime.tv_usec);
}

}  // namespace

int run_bare_client(const Place& place, const BenchShape& shape) {
  NodalConfig config;
  config.num_points = shape.nodes;
  try {
    const int fd = connect_to(place, 60.0);
    const auto request = negotiation_request_bytes(config);
    write_full(fd, request.data(), request.size());
    std::uint8_t reply = 0;
    if (read_full(fd, &reply, 1) != 1 || reply != 8) throw std::runtime_error("negotiation refused");
    std::vector<std::uint8_t> kin(1 + config.kinematics_payload_bytes());
    std::vector<std::uint8_t> loads(1 + config.loads_payload_bytes(), 0);
    loads[0] = 6;
    // The t0 exchange (LAMMPS: setup) is outside the timed loop, as in LAMMPS' loop time.
    if (read_full(fd, kin.data(), kin.size()) != kin.size()) throw std::runtime_error("no t0 kinematics");
    write_full(fd, loads.data(), loads.size());
    const auto t0 = std::chrono::steady_clock::now();
    auto t_last = t0;
    const double cpu0 = cpu_seconds();
    long exchanges = 0;
    for (;;) {
      // One recv, as fix mbdyn's: the 5 at the end comes alone (the peer then waits for our close).
      const long got = ::recv(fd, kin.data(), kin.size(), 0);
      if (got >= 1 && kin[0] == 5) break;
      if (got <= 0 || read_full(fd, kin.data() + got, kin.size() - got) != kin.size() - got)
        throw std::runtime_error("short kinematics message");
      write_full(fd, loads.data(), loads.size());
      t_last = std::chrono::steady_clock::now();
      ++exchanges;
    }
    const double cpu = cpu_seconds() - cpu0;
    ::close(fd);
    const double wall = std::chrono::duration<double>(t_last - t0).count();
    std::printf("mbdyn_bench_peer client: %ld exchanges, wall %.3f us, cpu %.3f us per exchange\n", exchanges,
                exchanges ? 1e6 * wall / exchanges : 0.0, exchanges ? 1e6 * cpu / exchanges : 0.0);
  } catch (const std::exception& e) {
    std::printf("mbdyn_bench_peer client: error: %s\n", e.what());
    return 1;
  }
  return 0;
}

}  // namespace dembridge::mbdyn::bench
