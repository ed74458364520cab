// mbdyn_bench_peer: the fast peer and the bare client of bench/run_mbdyn_exchange_bench.py.
//   mbdyn_bench_peer serve  (--path FILE | --port N) [--nodes N] [--messages K] [--origin x,y,z] [--spacing dx,dy,dz]
//                           [--orientation matrix|none] [--grid NX]
//   mbdyn_bench_peer client (--path FILE | --port N) [--nodes N] [--orientation matrix|none]
// --orientation none: the messages of `external structural mapping` (positions and velocities of
// the mapped points, forces back); --grid NX: the points on an NX-wide grid in the x-y plane.
#include <cstdio>
#include <cstdlib>
#include <sstream>
#include <string>

#include "exchange_bench.h"

using namespace dembridge::mbdyn::bench;

namespace {

[[noreturn]] void usage(const std::string& why) {
  std::fprintf(stderr,
               "mbdyn_bench_peer: %s\nusage: mbdyn_bench_peer serve|client (--path FILE | --port N) [--nodes N] "
               "[--messages K] [--origin x,y,z] [--spacing dx,dy,dz] [--orientation matrix|none] [--grid NX]\n",
               why.c_str());
  std::exit(64);
}

std::array<double, 3> parse_v3(const std::string& s) {
  std::array<double, 3> v{};
  char c1 = 0, c2 = 0;
  std::istringstream in(s);
  if (!(in >> v[0] >> c1 >> v[1] >> c2 >> v[2]) || c1 != ',' || c2 != ',') usage("expected x,y,z, got '" + s + "'");
  return v;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) usage("expected serve or client");
  const std::string mode = argv[1];
  Place place;
  BenchShape shape;
  long messages = 1001;
  for (int i = 2; i < argc; ++i) {
    const std::string a = argv[i];
    if (i + 1 >= argc) usage("missing value after " + a);
    const std::string v = argv[++i];
    if (a == "--path") place.unix_path = v;
    else if (a == "--port") place.tcp_port = std::atoi(v.c_str());
    else if (a == "--nodes") shape.nodes = static_cast<std::uint32_t>(std::atol(v.c_str()));
    else if (a == "--messages") messages = std::atol(v.c_str());
    else if (a == "--origin") shape.origin = parse_v3(v);
    else if (a == "--spacing") shape.spacing = parse_v3(v);
    else if (a == "--grid") shape.grid = static_cast<std::uint32_t>(std::atol(v.c_str()));
    else if (a == "--orientation") {
      if (v != "none" && v != "matrix") usage("expected --orientation matrix or none, got '" + v + "'");
      shape.orientation_none = v == "none";
    }
    else usage("unknown option " + a);
  }
  if (place.unix_path.empty() && place.tcp_port < 0) usage("expected --path or --port");
  if (shape.nodes == 0 || messages < 1) usage("expected --nodes >= 1 and --messages >= 1");
  if (mode == "serve") return run_fast_peer(place, shape, messages);
  if (mode == "client") return run_bare_client(place, shape);
  usage("expected serve or client, got " + mode);
}
