// FileSession (coupling/protocol/file_session.h), MBDyn's file communicator on the peer's side:
// OUT read then removed, its payload in the socket's wire layout, IN written through IN.tmp and a
// rename, timeouts naming the file, and an IN found at the start refused and left untouched.
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <sys/stat.h>
#include <unistd.h>

#include "file_session.h"
#include "protocol_error.h"

namespace mb = dembridge::mbdyn;

namespace {
bool exists(const std::string& p) {
  struct stat st;
  return ::stat(p.c_str(), &st) == 0;
}
std::string slurp(const std::string& p) {
  std::ifstream f(p);
  std::ostringstream s;
  s << f.rdbuf();
  return s.str();
}
void put(const std::string& p, const std::string& text) { std::ofstream(p) << text; }

struct Folder {
  std::string dir;
  Folder() {
    char tmpl[] = "/tmp/fsessXXXXXX";
    dir = ::mkdtemp(tmpl);
  }
  ~Folder() { std::filesystem::remove_all(dir); }
  mb::FileOptions options(double timeout = 5) const {
    mb::FileOptions o;
    o.in_path = dir + "/IN.dat";
    o.out_path = dir + "/OUT.dat";
    o.sleep_s = 0.001;
    o.timeout_s = timeout;
    o.nodal.num_points = 2;
    o.nodal.rotation = mb::Rotation::None;
    o.nodal.labels = true;
    return o;
  }
};
}  // namespace

TEST(FileSession, ReadsAndRemovesOutAndGivesTheWireLayout) {
  Folder d;
  mb::FileSession s(d.options());
  put(d.dir + "/OUT.dat", "# regular nodes\n20 1 2 3 4 5 6\n30 -1 -2 -3 -4 -5 -6.5\n");
  const mb::Received r = s.receive();
  EXPECT_TRUE(r.is_kinematics());
  EXPECT_EQ(r.step, 0u);
  EXPECT_FALSE(exists(d.dir + "/OUT.dat"));  // MBDyn's `no clobber` waits for this
  const auto& raw = s.raw_payload();
  ASSERT_EQ(raw.size(), d.options().nodal.kinematics_payload_bytes());
  const mb::Kinematics k = mb::decode_kinematics(d.options().nodal, mb::Command::RegularDataAndGotoNextStep, raw.data(),
                                                 raw.size());
  EXPECT_EQ(k.labels, (std::vector<std::uint32_t>{20, 30}));
  EXPECT_EQ(k.x, (std::vector<double>{1, 2, 3, -1, -2, -3}));
  EXPECT_EQ(k.v, (std::vector<double>{4, 5, 6, -4, -5, -6.5}));
  EXPECT_EQ(s.kinematics().v, k.v);
}

TEST(FileSession, WritesInAtomicallyWithTheReceivedLabels) {
  Folder d;
  mb::FileSession s(d.options());
  put(d.dir + "/OUT.dat", "30 0 0 0 0 0 0\n20 0 0 0 0 0 0\n");
  s.receive();
  mb::Loads l(d.options().nodal);
  l.force = {-5, 0.5, 0, 1, 2, 3};
  s.send_loads(l);
  EXPECT_EQ(slurp(d.dir + "/IN.dat"),
            "30 -5.0000000000000000e+00 5.0000000000000000e-01 0.0000000000000000e+00\n"
            "20 1.0000000000000000e+00 2.0000000000000000e+00 3.0000000000000000e+00\n");
  EXPECT_FALSE(exists(d.dir + "/IN.dat.tmp"));
}

TEST(FileSession, TimeoutsNameTheFile) {
  Folder d;
  mb::FileSession s(d.options(0.05));
  try {
    s.receive();
    FAIL() << "no timeout";
  } catch (const mb::TimeoutError& e) {
    EXPECT_NE(std::string(e.what()).find("MBDyn wrote no " + d.dir + "/OUT.dat"), std::string::npos) << e.what();
  }
  put(d.dir + "/OUT.dat", "1 0 0 0 0 0 0\n2 0 0 0 0 0 0\n");
  s.receive();
  put(d.dir + "/IN.dat", "MBDyn has not read this yet\n");
  try {
    s.send_loads(mb::Loads(d.options().nodal));
    FAIL() << "no timeout";
  } catch (const mb::TimeoutError& e) {
    EXPECT_NE(std::string(e.what()).find("did not read (unlink) its previous input file"), std::string::npos) << e.what();
  }
  EXPECT_EQ(slurp(d.dir + "/IN.dat"), "MBDyn has not read this yet\n");  // not clobbered
}

TEST(FileSession, AnInFoundAtTheStartIsRefusedAndKept) {
  for (const char* name : {"/IN.dat", "/IN.dat.tmp"}) {
    Folder d;
    put(d.dir + name, "a user's file\n");
    EXPECT_THROW(mb::FileSession s(d.options()), mb::SystemError) << name;
    EXPECT_EQ(slurp(d.dir + name), "a user's file\n");
  }
  Folder d;
  mb::FileOptions o = d.options();
  o.nodal.reference_node = true;
  EXPECT_THROW(mb::FileSession s(o), std::invalid_argument);
}
