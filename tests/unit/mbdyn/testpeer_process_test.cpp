// The mbdyn_testpeer executable as a separate process, the way Python/LAMMPS tests will use it:
// a full coupling over Unix and TCP, and MBDyn killed with SIGKILL in the middle of a run.
#include <gtest/gtest.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <fstream>
#include <iterator>
#include <cmath>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "protocol_error.h"
#include "test_support.h"

extern char** environ;

using namespace dembridge::mbdyn;

namespace {

// A child process with its stdout on a pipe.
class PeerProcess {
 public:
  explicit PeerProcess(const std::vector<std::string>& args) {
    int out[2];
    if (::pipe(out) != 0) throw std::runtime_error("pipe");
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_adddup2(&actions, out[1], 1);
    posix_spawn_file_actions_addclose(&actions, out[0]);
    std::vector<char*> argv{const_cast<char*>(DEMBRIDGE_MBDYN_TESTPEER)};
    for (const auto& a : args) argv.push_back(const_cast<char*>(a.c_str()));
    argv.push_back(nullptr);
    if (posix_spawn(&pid_, DEMBRIDGE_MBDYN_TESTPEER, &actions, nullptr, argv.data(), environ) != 0)
      throw std::runtime_error("posix_spawn mbdyn_testpeer");
    posix_spawn_file_actions_destroy(&actions);
    ::close(out[1]);
    stdout_ = ::fdopen(out[0], "r");
  }
  ~PeerProcess() {
    if (pid_ > 0) {
      ::kill(pid_, SIGKILL);
      ::waitpid(pid_, nullptr, 0);
    }
    if (stdout_) ::fclose(stdout_);
  }
  std::string read_line() {
    char buf[512];
    return std::fgets(buf, sizeof buf, stdout_) ? std::string(buf) : std::string();
  }
  // Exit status, or -signal; waits at most timeout_s, then kills.
  int wait(double timeout_s) {
    const auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(timeout_s);
    int status = 0;
    while (::waitpid(pid_, &status, WNOHANG) == 0) {
      if (std::chrono::steady_clock::now() > end) {
        ADD_FAILURE() << "mbdyn_testpeer did not exit within " << timeout_s << " s";
        ::kill(pid_, SIGKILL);
        ::waitpid(pid_, &status, 0);
        break;
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    pid_ = -1;
    return WIFEXITED(status) ? WEXITSTATUS(status) : -WTERMSIG(status);
  }
  pid_t pid() const { return pid_; }

 private:
  pid_t pid_ = -1;
  FILE* stdout_ = nullptr;
};

// Spring F = -k x on every point, loose coupling, until MBDyn's 5.
int run_springs(PeerSession& s, double k) {
  int messages = 0;
  while (s.receive().is_kinematics()) {
    ++messages;
    Loads loads(s.config());
    for (std::size_t i = 0; i < loads.force.size(); ++i) loads.force[i] = -k * s.kinematics().x[i];
    s.send_loads(loads, true);
  }
  return messages;
}

}  // namespace

TEST(TestPeerProcess, FullLooseCouplingOverUnixAndTcp) {
  for (bool tcp : {false, true}) {
    SCOPED_TRACE(tcp ? "tcp" : "unix");
    const std::string path = test::unique_socket_path("proc");
    const std::string trajectory = path + ".traj";
    std::vector<std::string> args{"--nodes", "2", "--orientation", "vector", "--labels", "--steps", "100",
                                  "--dt", "0.01", "--mass", "1", "--trajectory", trajectory,
                                  "--accept-timeout", "10", "--io-timeout", "10"};
    if (tcp) {
      args.insert(args.end(), {"--port", "0"});
    } else {
      args.insert(args.end(), {"--path", path});
    }
    PeerProcess peer(args);
    SessionOptions o;
    o.nodal.num_points = 2;
    o.nodal.rotation = Rotation::OrientationVector;
    o.nodal.labels = true;
    o.connect_timeout_s = 10;
    o.io_timeout_s = 10;
    if (tcp) {
      int port = -1;
      std::sscanf(peer.read_line().c_str(), "mbdyn_testpeer: listening on port %d", &port);
      ASSERT_GT(port, 0);
      o.endpoint = Endpoint::tcp("127.0.0.1", static_cast<std::uint16_t>(port));
    } else {
      o.endpoint = Endpoint::unix_path(path);
    }
    PeerSession s = PeerSession::open(o);
    EXPECT_EQ(run_springs(s, 4 * 3.141592653589793 * 3.141592653589793), 101);
    EXPECT_EQ(peer.wait(10), 0);
    // One period of x(t) = x0 cos(2 pi t): node 1 (x0 = 1) is back near 1 after t = 1.
    std::ifstream f(trajectory);
    std::string line, last;
    int lines = 0;
    while (std::getline(f, line))
      if (!line.empty() && line[0] != '#') {
        last = line;
        ++lines;
      }
    EXPECT_EQ(lines, 101);
    std::istringstream in(last);
    std::vector<double> v{std::istream_iterator<double>(in), std::istream_iterator<double>()};
    ASSERT_EQ(v.size(), 1u + 2 * 8);
    EXPECT_NEAR(v[0], 1.0, 1e-12);
    EXPECT_NEAR(v[1 + 8], 1.0 * std::cos(2 * 3.141592653589793) + 0.0, 2e-2);
    std::remove(trajectory.c_str());
  }
}

TEST(TestPeerProcess, MbdynKilledMidRunIsReportedWithinTheTimeout) {
  const std::string path = test::unique_socket_path("kill");
  PeerProcess peer({"--path", path, "--nodes", "1", "--steps", "1000000", "--io-timeout", "10"});
  SessionOptions o;
  o.endpoint = Endpoint::unix_path(path);
  o.nodal.num_points = 1;
  o.connect_timeout_s = 10;
  o.io_timeout_s = 5;
  PeerSession s = PeerSession::open(o);
  for (int i = 0; i < 50; ++i) {
    ASSERT_TRUE(s.receive().is_kinematics());
    s.send_loads(Loads(s.config()), true);
  }
  ::kill(peer.pid(), SIGKILL);
  const auto t0 = std::chrono::steady_clock::now();
  try {
    for (int i = 0; i < 1000000; ++i) {
      if (!s.receive().is_kinematics()) break;
      s.send_loads(Loads(s.config()), true);
    }
    FAIL() << "expected PeerClosedError";
  } catch (const PeerClosedError& e) {
    // Killed between messages, between command byte and payload, or while we write: EOF,
    // ECONNRESET or EPIPE, always a PeerClosedError naming what was expected.
    const std::string what = e.what();
    EXPECT_TRUE(what.find("MBDyn closed the connection") == 0 || what.find("MBDyn reset the connection") == 0) << what;
  }
  EXPECT_LT(test::seconds_since(t0), 1.0);
  EXPECT_EQ(peer.wait(5), -SIGKILL);
}
