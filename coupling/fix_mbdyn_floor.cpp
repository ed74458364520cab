// fix mbdyn/floor: the floor fix mbdyn is measured against (issue 12, P5; a bench instrument, see
// doc/benchmarks.md). It does the bare client's exchange (coupling/benchpeer/bare_exchange.h:
// plain blocking recv and send of the same messages, no decoding, zero loads, no timeouts) at the
// points of the step where fix mbdyn does its own (receive in post_integrate, answer in
// post_force), and times them with the same `profile yes` clock. So in a coupled run of 10^4
// particles it meets the same cache pollution and the same peer, and its share of the step is the
// least any implementation of the exchange over this socket can cost there. Moves no atom.
//   fix ID group mbdyn/floor (path FILE | port N) nodes N [profile yes|no]
// Rank 0 alone talks to the peer.
#include "comm.h"
#include "error.h"
#include "fix.h"
#include "update.h"
#include "utils.h"

#include "bare_exchange.h"
#include "command_args.h"
#include "exchange_profile.h"
#include "style_registry.h"

#include <climits>
#include <memory>
#include <optional>
#include <string>

using namespace LAMMPS_NS;
using namespace LAMMPS_NS::FixConst;

namespace dembridge {

namespace {

class FixMBDynFloor : public Fix {
 public:
  FixMBDynFloor(LAMMPS *lmp, int narg, char **arg) : Fix(lmp, narg, arg)
  {
    const std::string prefix = std::string("Fix mbdyn/floor (id ") + id + "): ";
    for (int i = 3; i < narg; i += 2) {
      const std::string kw = arg[i];
      if (i + 1 >= narg) error->all(FLERR, prefix + "keyword '" + kw + "' expects a value, but the command ends there");
      const std::string v = arg[i + 1];
      if (kw == "path") {
        place_.unix_path = v;
      } else if (kw == "port") {
        const std::optional<long long> port = args::integer(lmp, v);
        place_.tcp_port = port && *port >= 1 && *port <= 65535 ? int(*port) : -1;
        if (place_.tcp_port < 1)
          error->all(FLERR, prefix + "keyword 'port' expects a TCP port number (1-65535), got " + v);
      } else if (kw == "nodes") {
        const std::optional<long long> n = args::integer(lmp, v);
        nodes_ = n && *n >= 1 && *n <= INT_MAX ? int(*n) : 0;
        if (nodes_ < 1) error->all(FLERR, prefix + "keyword 'nodes' expects a positive node count, got " + v);
      } else if (kw == "profile") {
        if (v != "yes" && v != "no") error->all(FLERR, prefix + "keyword 'profile' expects yes or no, got '" + v + "'");
        if (v == "yes") profile_.enable();
      } else {
        error->all(FLERR, prefix + "unknown keyword '" + kw + "'; expected path, port, nodes or profile");
      }
    }
    if (place_.unix_path.empty() == (place_.tcp_port < 0))
      error->all(FLERR, prefix + "give exactly one socket: 'path FILE' or 'port N' (127.0.0.1)");
    if (nodes_ < 1) error->all(FLERR, prefix + "missing 'nodes N' (the node count of MBDyn's element)");
  }

  int setmask() override { return POST_INTEGRATE | POST_FORCE; }

  void setup(int) override
  {
    profile_.start_run();
    if (comm->me != 0 || peer_) return;
    try {  // connect, negotiate, t0 kinematics and their answer, as fix mbdyn's set-up
      peer_ = std::make_unique<mbdyn::bench::BareExchange>(place_, static_cast<std::uint32_t>(nodes_), 60.0);
      peer_->send();
    } catch (const std::exception &e) {
      error->one(FLERR, std::string("Fix mbdyn/floor: ") + e.what());
    }
  }

  void post_integrate() override
  {
    profile_.start_step();
    if (comm->me != 0) return;
    profile_.begin();
    bool got = false;
    try {
      got = peer_->receive();
    } catch (const std::exception &e) {
      error->one(FLERR, std::string("Fix mbdyn/floor: ") + e.what());
    }
    profile_.lap(ExchangeProfile::Receive);
    if (!got) error->one(FLERR, "Fix mbdyn/floor: the peer ended (sent 5) at step " + std::to_string(update->ntimestep));
  }

  void post_force(int) override
  {
    if (comm->me != 0) return;
    profile_.begin();
    try {
      peer_->send();
    } catch (const std::exception &e) {
      error->one(FLERR, std::string("Fix mbdyn/floor: ") + e.what());
    }
    profile_.lap(ExchangeProfile::Loads);
  }

  void post_run() override
  {
    if (comm->me == 0 && profile_.enabled())
      utils::logmesg(lmp, profile_.summary(std::string("Fix mbdyn/floor (id ") + id + ")"));
  }

 private:
  mbdyn::bench::Place place_;
  int nodes_ = 0;
  std::unique_ptr<mbdyn::bench::BareExchange> peer_;  // rank 0; its destructor reads the peer's 5 and closes
  ExchangeProfile profile_;
};

void *create_fix_mbdyn_floor(void *lmp, int narg, char **arg)
{
  return new FixMBDynFloor(static_cast<LAMMPS *>(lmp), narg, arg);
}

}  // namespace

static RegisterStyle reg_fix_mbdyn_floor("fix", "mbdyn/floor",
                                         "bench instrument: the bare MBDyn exchange fix mbdyn is measured against",
                                         create_fix_mbdyn_floor);

}  // namespace dembridge
