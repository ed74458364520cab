// The protocol library's guards against a broken peer or a user's file, directly: the rotation
// check fix mbdyn applies to every orientation matrix MBDyn sends, and the stale-socket removal of
// `create no` (which must never delete anything but a socket nobody listens on).
#include <gtest/gtest.h>

#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/un.h>
#include <unistd.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <string>

#include "protocol_error.h"
#include "rotation_check.h"
#include "stale_socket.h"

using namespace dembridge::mbdyn;

namespace {

using M3 = std::array<double, 9>;

M3 rz_rx(double a, double b) {  // Rz(a) Rx(b), row-major, written out
  const double ca = std::cos(a), sa = std::sin(a), cb = std::cos(b), sb = std::sin(b);
  return {ca, -sa * cb, sa * sb, sa, ca * cb, -ca * sb, 0, sb, cb};
}

std::string scratch(const char* name) {
  return "/tmp/dembridge-unit-" + std::to_string(::getpid()) + "-" + name;
}

bool exists(const std::string& p) {
  struct stat st {};
  return ::lstat(p.c_str(), &st) == 0;
}

int bound_socket(const std::string& path, bool listening) {
  const int fd = ::socket(AF_UNIX, SOCK_STREAM, 0);
  sockaddr_un a{};
  a.sun_family = AF_UNIX;
  std::snprintf(a.sun_path, sizeof a.sun_path, "%s", path.c_str());
  EXPECT_EQ(::bind(fd, reinterpret_cast<sockaddr*>(&a), sizeof a), 0);
  if (listening) {
    EXPECT_EQ(::listen(fd, 1), 0);
  }
  return fd;
}

}  // namespace

TEST(RotationCheck, AcceptsRotationsAndNamesEachDefect) {
  EXPECT_EQ(rotation_matrix_defect({1, 0, 0, 0, 1, 0, 0, 0, 1}), "");
  EXPECT_EQ(rotation_matrix_defect(rz_rx(0.3, -1.2)), "");
  M3 near = rz_rx(2.0, 0.7);
  near[4] += 1e-9;  // round-off far beyond MBDyn's, still accepted
  EXPECT_EQ(rotation_matrix_defect(near), "");
  EXPECT_EQ(rotation_matrix_defect({0, 0, 0, 0, 0, 0, 0, 0, 0}), "is all zero");
  M3 scaled = rz_rx(0.3, 0.1);
  for (double& r : scaled) r *= 1.001;
  EXPECT_EQ(rotation_matrix_defect(scaled).rfind("is not orthonormal: max |R^T R - I| = 0.002", 0), 0u)
      << rotation_matrix_defect(scaled);
  M3 sheared = {1, 0.3, 0, 0, 1, 0, 0, 0, 1};
  EXPECT_NE(rotation_matrix_defect(sheared).find("tolerance 1e-06"), std::string::npos);
  EXPECT_EQ(rotation_matrix_defect({1, 0, 0, 0, 1, 0, 0, 0, -1}), "has determinant -1: a reflection, not a rotation");
  M3 off = rz_rx(0.5, 0.5);
  off[0] += 2e-6;  // beyond the tolerance
  EXPECT_NE(rotation_matrix_defect(off), "");
}

TEST(StaleSocket, RemovesOnlyASocketNobodyListensOn) {
  const std::string none = scratch("none.sock");
  EXPECT_NO_THROW(remove_stale_unix_socket(none));  // nothing there

  const std::string file = scratch("results.txt");
  std::ofstream(file) << "a user's file\n";
  try {
    remove_stale_unix_socket(file);
    ADD_FAILURE() << "a regular file was accepted";
  } catch (const SystemError& e) {
    EXPECT_NE(std::string(e.what()).find("'" + file + "' exists and is a regular file, not a socket"), std::string::npos)
        << e.what();
  }
  std::ifstream in(file);
  std::string line;
  std::getline(in, line);
  EXPECT_EQ(line, "a user's file");
  ::unlink(file.c_str());

  const std::string stale = scratch("stale.sock");
  ::close(bound_socket(stale, false));  // the file stays, nobody listens
  ASSERT_TRUE(exists(stale));
  EXPECT_NO_THROW(remove_stale_unix_socket(stale));
  EXPECT_FALSE(exists(stale));

  const std::string live = scratch("live.sock");
  const int fd = bound_socket(live, true);
  EXPECT_THROW(remove_stale_unix_socket(live), SystemError);
  EXPECT_TRUE(exists(live));
  ::close(fd);
  ::unlink(live.c_str());
}
