// The file communicator's text formats (coupling/protocol/file_text.h) on MBDyn's own lines: an OUT
// line the real MBDyn 1.7.3 wrote (tests/data/mbdyn-ext/file_communicator, orientation none), the
// row-by-row matrix of the OUT file against the wire's column-major order, exact round trips at
// 16 digits, and every malformed file named with its line.
#include <gtest/gtest.h>

#include <string>

#include "file_text.h"
#include "protocol_error.h"

namespace mb = dembridge::mbdyn;

namespace {
mb::NodalConfig config(std::uint32_t n, mb::Rotation r, bool labels, bool acc = false) {
  mb::NodalConfig c;
  c.num_points = n;
  c.rotation = r;
  c.labels = labels;
  c.accelerations = acc;
  return c;
}

std::string thrown(const mb::NodalConfig& c, const std::string& text) {
  mb::Kinematics k;
  try {
    mb::parse_kinematics_text(c, text, "OUT.dat", k);
  } catch (const mb::MalformedMessageError& e) {
    return e.what();
  }
  return "";
}
}  // namespace

TEST(FileText, ParsesAnOutFileOfTheRealMbdyn) {
  // OUT.0002 of the recorded run, verbatim
  const std::string text =
      "# regular nodes\n9.9979999980000012e-02 0.0000000000000000e+00 0.0000000000000000e+00 "
      "-1.0000010000000000e-02 0.0000000000000000e+00 0.0000000000000000e+00\n";
  mb::Kinematics k;
  mb::parse_kinematics_text(config(1, mb::Rotation::None, false), text, "OUT.dat", k);
  ASSERT_EQ(k.x.size(), 3u);
  EXPECT_EQ(k.x[0], 9.9979999980000012e-02);
  EXPECT_EQ(k.v[0], -1.0000010000000000e-02);
  EXPECT_EQ(k.x[1], 0.0);
  EXPECT_TRUE(k.orientation.empty() && k.omega.empty());
  // and MBDyn's line back, at its precision 16
  EXPECT_EQ(mb::format_kinematics_text(config(1, mb::Rotation::None, false), k, 16), text);
}

TEST(FileText, MatrixRowByRowInTheFileColumnMajorInKinematics) {
  const auto c = config(2, mb::Rotation::OrientationMatrix, true, true);
  // point 7: R rows (0 -1 0) (1 0 0) (0 0 1), a rotation by +90 degrees about z
  const std::string text =
      "# regular nodes\n7 1 2 3 0 -1 0 1 0 0 0 0 1 4 5 6 0 0 0.5 7 8 9 0.1 0.2 0.3\n"
      "9 -1 -2 -3 1 0 0 0 1 0 0 0 1 0 0 0 0 0 0 0 0 0 0 0 0\n";
  mb::Kinematics k;
  mb::parse_kinematics_text(c, text, "OUT.dat", k);
  EXPECT_EQ(k.labels, (std::vector<std::uint32_t>{7, 9}));
  const mb::Matrix3 R = k.rotation_matrix(0);
  EXPECT_EQ(R, (mb::Matrix3{0, -1, 0, 1, 0, 0, 0, 0, 1}));
  EXPECT_EQ(k.orientation[1], 1.0);  // wire order: R11 R21 ...
  EXPECT_EQ(k.omega[2], 0.5);
  EXPECT_EQ(k.a[2], 9.0);
  EXPECT_EQ(k.omega_dot[2], 0.3);
  mb::Kinematics back;
  mb::parse_kinematics_text(c, mb::format_kinematics_text(c, k, 16), "again", back);
  EXPECT_EQ(back.orientation, k.orientation);
  EXPECT_EQ(back.x, k.x);
  EXPECT_EQ(back.omega_dot, k.omega_dot);
}

TEST(FileText, LoadsRoundTripExactlyAtSixteenDigits) {
  const auto c = config(2, mb::Rotation::OrientationVector, true);
  mb::Loads l(c);
  l.force = {-5.0, 0.1, 1.0 / 3.0, 2e-300, -0.0, 7.25};
  l.moment = {1e10, -2.0 / 7.0, 0, 0, 0, 3.0};
  const std::string text = mb::format_loads_text(c, l, {20, 30}, 16);
  EXPECT_EQ(text.substr(0, 3), "20 ");
  const mb::Loads back = mb::parse_loads_text(c, text, "IN.dat");
  EXPECT_EQ(back.force, l.force);
  EXPECT_EQ(back.moment, l.moment);
  EXPECT_EQ(back.labels, (std::vector<std::uint32_t>{20, 30}));
  // orientation none: forces only, 3 values a line
  const auto n = config(1, mb::Rotation::None, false);
  mb::Loads f(n);
  f.force = {-5.0, -0.0, -0.0};
  EXPECT_EQ(mb::format_loads_text(n, f, {}, 16), "-5.0000000000000000e+00 -0.0000000000000000e+00 -0.0000000000000000e+00\n");
}

TEST(FileText, MalformedFilesAreNamedWithTheirLine) {
  const auto c = config(1, mb::Rotation::None, false);
  EXPECT_NE(thrown(c, "# regular nodes\n").find("OUT.dat: expected 1 point line(s) (x y z v(3)), found 0"),
            std::string::npos);
  EXPECT_NE(thrown(c, "# regular nodes\n1 2 3 4 5\n").find("OUT.dat line 2: expected 6 values (x y z v(3)), found 5"),
            std::string::npos);
  EXPECT_NE(thrown(c, "1 2 3 4 5 nan\n").find("line 1: v expects a finite number, got 'nan'"), std::string::npos);
  EXPECT_NE(thrown(c, "1 2 3x 4 5 6\n").find("line 1: x expects a finite number, got '3x'"), std::string::npos);
  EXPECT_NE(thrown(config(1, mb::Rotation::None, true), "-4 1 2 3 4 5 6\n").find("expected a label (an integer), got '-4'"),
            std::string::npos);
  EXPECT_THROW(mb::parse_loads_text(c, "1 2\n", "IN.dat"), mb::MalformedMessageError);
  mb::NodalConfig r = c;
  r.reference_node = true;
  mb::Kinematics k;
  EXPECT_THROW(mb::parse_kinematics_text(r, "", "OUT.dat", k), std::invalid_argument);
}
