#include <sys/resource.h>

#include <chrono>
#include <cstdio>
#include <stdexcept>

#include "bare_exchange.h"
#include "exchange_bench.h"

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
  try {
    BareExchange x(place, shape.nodes, 60.0, shape.rotation());
    // The t0 exchange (LAMMPS: setup) is outside the timed loop, as in LAMMPS' loop time.
    x.send();
    const auto t0 = std::chrono::steady_clock::now();
    auto t_last = t0;
    const double cpu0 = cpu_seconds();
    long exchanges = 0;
    while (x.receive()) {
      x.send();
      t_last = std::chrono::steady_clock::now();
      ++exchanges;
    }
    const double cpu = cpu_seconds() - cpu0;
    x.finish();
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
