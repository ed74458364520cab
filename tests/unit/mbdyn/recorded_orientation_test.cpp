// The orientation layout of the protocol library against the real MBDyn 1.7.3: the converged
// kinematics messages of a recorded `external structural` run with a reference node, labels and
// orientation matrices (tests/data/mbdyn/refnode, README there), decoded by the library, must give
// the node states MBDyn itself wrote to its .mov (position, Euler 1-2-3 angles in degrees,
// velocity, angular velocity) at the same steps. The points arrive relative to the reference node
// and in its frame; they are made absolute here with MBDyn's definitions (x = x_r + R_r x~,
// R = R_r R~, v = v_r + w_r x (R_r x~) + R_r v~, w = w_r + R_r w~). A swapped field order, a
// transposed matrix or a label block of the wrong size moves these by O(0.1 .. 1).
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "nodal_config.h"
#include "nodal_message.h"

using namespace dembridge::mbdyn;

namespace {

using M3 = std::array<double, 9>;  // row-major
using V3 = std::array<double, 3>;

const std::string kDir = std::string(DEMBRIDGE_MBDYN_DATA) + "/refnode/";

// The transcript's values in wire order: an integer token is a uint32 field (label, pad), any
// other (it has a '.', 'e', inf or nan) a double.
std::vector<std::uint8_t> wire_bytes(const std::string& values) {
  std::vector<std::uint8_t> out;
  std::istringstream in(values);
  for (std::string tok; in >> tok;) {
    if (tok.find_first_not_of("0123456789") == std::string::npos) {
      const std::uint32_t u = static_cast<std::uint32_t>(std::stoul(tok));
      const auto* p = reinterpret_cast<const std::uint8_t*>(&u);
      out.insert(out.end(), p, p + 4);
    } else {
      const double d = std::stod(tok);
      const auto* p = reinterpret_cast<const std::uint8_t*>(&d);
      out.insert(out.end(), p, p + 8);
    }
  }
  return out;
}

M3 mul(const M3& a, const M3& b) {
  M3 c{};
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      for (int k = 0; k < 3; ++k) c[3 * i + j] += a[3 * i + k] * b[3 * k + j];
  return c;
}
V3 mul(const M3& a, const V3& v) {
  return {a[0] * v[0] + a[1] * v[1] + a[2] * v[2], a[3] * v[0] + a[4] * v[1] + a[5] * v[2],
          a[6] * v[0] + a[7] * v[1] + a[8] * v[2]};
}
V3 cross(const V3& a, const V3& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
V3 add(const V3& a, const V3& b) { return {a[0] + b[0], a[1] + b[1], a[2] + b[2]}; }

// MBDyn's .mov angles: Euler 1-2-3 in degrees, R = Rx(a) Ry(b) Rz(c), written out here.
M3 from_mov_euler(double a_deg, double b_deg, double c_deg) {
  const double d = M_PI / 180.0, a = a_deg * d, b = b_deg * d, c = c_deg * d;
  const M3 rx{1, 0, 0, 0, std::cos(a), -std::sin(a), 0, std::sin(a), std::cos(a)};
  const M3 ry{std::cos(b), 0, std::sin(b), 0, 1, 0, -std::sin(b), 0, std::cos(b)};
  const M3 rz{std::cos(c), -std::sin(c), 0, std::sin(c), std::cos(c), 0, 0, 0, 1};
  return mul(mul(rx, ry), rz);
}

struct MovRow {
  V3 x, euler, v, w;
};

template <std::size_t N>
double worst(const std::array<double, N>& a, const std::array<double, N>& b) {
  double m = 0;
  for (std::size_t i = 0; i < N; ++i) m = std::max(m, std::fabs(a[i] - b[i]));
  return m;
}

}  // namespace

TEST(RecordedOrientation, ReferenceNodeMatricesDecodeToMbdynsOwnNodeStates) {
  std::ifstream kin(kDir + "tight_converged.csv"), mov(kDir + "tight_steps.mov");
  ASSERT_TRUE(kin && mov) << "missing " << kDir << "tight_converged.csv / tight_steps.mov";
  std::string line;
  std::getline(kin, line);  // "# negotiation FLAGS N"
  std::istringstream neg(line.substr(line.find("negotiation") + 11));
  std::uint32_t flags = 0, n = 0;
  neg >> flags >> n;
  const NodalConfig config = NodalConfig::from_flags(flags, n);
  ASSERT_EQ(config.rotation, Rotation::OrientationMatrix);
  ASSERT_TRUE(config.reference_node && config.labels);
  ASSERT_EQ(n, 3u);
  std::getline(kin, line);  // header
  double dev_x = 0, dev_R = 0, dev_v = 0, dev_w = 0, max_angle = 0;
  int messages = 0;
  while (std::getline(kin, line)) {
    std::istringstream row(line);
    std::string step, cmd, values;
    std::getline(row, step, ',');
    std::getline(row, cmd, ',');
    std::getline(row, values);
    const std::vector<std::uint8_t> bytes = wire_bytes(values);
    ASSERT_EQ(bytes.size(), config.kinematics_payload_bytes()) << "step " << step;
    const Kinematics k = decode_kinematics(config, static_cast<Command>(std::stoi(cmd)), bytes.data(), bytes.size());
    std::map<std::uint32_t, MovRow> node;  // the .mov rows of this step: REF then the points
    for (int r = 0; r < 4; ++r) {
      std::uint32_t label;
      MovRow m;
      ASSERT_TRUE(mov >> label >> m.x[0] >> m.x[1] >> m.x[2] >> m.euler[0] >> m.euler[1] >> m.euler[2] >> m.v[0] >>
                  m.v[1] >> m.v[2] >> m.w[0] >> m.w[1] >> m.w[2]);
      node[label] = m;
    }
    ASSERT_EQ(k.reference.label, 10u);
    const MovRow& ref = node.at(10);
    const M3 Rr = k.reference_rotation_matrix();
    dev_x = std::max(dev_x, worst(k.reference.x, ref.x));
    dev_R = std::max(dev_R, worst(Rr, from_mov_euler(ref.euler[0], ref.euler[1], ref.euler[2])));
    dev_v = std::max(dev_v, worst(k.reference.v, ref.v));
    dev_w = std::max(dev_w, worst(k.reference.omega, ref.w));
    max_angle = std::max(max_angle, std::fabs(ref.euler[2]));
    ASSERT_EQ(k.labels.size(), 3u);
    for (std::size_t i = 0; i < 3; ++i) {
      const MovRow& p = node.at(k.labels[i]);
      const V3 d = mul(Rr, k.position(i));
      const V3 x = add(k.reference.x, d);
      const M3 R = mul(Rr, k.rotation_matrix(i));
      const V3 v = add(add(k.reference.v, cross(k.reference.omega, d)), mul(Rr, k.velocity(i)));
      const V3 w = add(k.reference.omega, mul(Rr, V3{k.omega[3 * i], k.omega[3 * i + 1], k.omega[3 * i + 2]}));
      dev_x = std::max(dev_x, worst(x, p.x));
      dev_R = std::max(dev_R, worst(R, from_mov_euler(p.euler[0], p.euler[1], p.euler[2])));
      dev_v = std::max(dev_v, worst(v, p.v));
      dev_w = std::max(dev_w, worst(w, p.w));
    }
    ++messages;
  }
  EXPECT_EQ(messages, 41);
  EXPECT_GT(max_angle, 10.0);  // the reference node has turned by 11.8 degrees at the end
  // Measured: x 3.1e-15, R 9.3e-15, v 1.7e-15, w 1.1e-16 (the .mov has 17 significant digits).
  EXPECT_LT(dev_x, 1e-12);
  EXPECT_LT(dev_R, 1e-12);
  EXPECT_LT(dev_v, 1e-12);
  EXPECT_LT(dev_w, 1e-12);
  std::printf("recorded refnode: %d messages, max deviation x %.2g R %.2g v %.2g w %.2g\n", messages, dev_x, dev_R,
              dev_v, dev_w);
}
