// Every message layout through both independent implementations: kinematics encoded by the test
// peer and decoded by the library, loads encoded by the library and decoded by the test peer,
// for all 4 orientations x labels x accelerations x reference node x N = 0..3.
#include <gtest/gtest.h>

#include <random>

#include "nodal_message.h"
#include "protocol_error.h"
#include "test_support.h"
#include "testpeer_wire.h"

using namespace dembridge::mbdyn;
namespace tp = dembridge::mbdyn::testpeer;

namespace {

std::vector<NodalConfig> all_configs() {
  std::vector<NodalConfig> out;
  for (Rotation r : {Rotation::None, Rotation::OrientationVector, Rotation::OrientationMatrix, Rotation::Euler123})
    for (int bits = 0; bits < 8; ++bits)
      for (std::uint32_t n = 0; n <= 3; ++n) {
        NodalConfig c;
        c.num_points = n;
        c.rotation = r;
        c.labels = bits & 1;
        c.accelerations = bits & 2;
        c.reference_node = bits & 4;
        if (n == 0 && !c.reference_node) continue;
        out.push_back(c);
      }
  return out;
}

tp::NodeState random_node(std::mt19937& rng, std::uint32_t label) {
  std::uniform_real_distribution<double> u(-10, 10), ang(-1.4, 1.4);
  auto v3 = [&]() { return tp::V3{u(rng), u(rng), u(rng)}; };
  tp::NodeState n;
  n.label = label;
  n.x = v3();
  n.v = v3();
  n.w = v3();
  n.a = v3();
  n.wdot = v3();
  // Euler angles within +-80 degrees keep the 1-2-3 decomposition unique.
  n.R = tp::multiply(tp::rotation_about_x(ang(rng)), tp::multiply(tp::rotation_about_y(ang(rng)), tp::rotation_about_z(ang(rng))));
  return n;
}

void expect_v3(const tp::V3& want, const double* got, const char* what) {
  for (int k = 0; k < 3; ++k) EXPECT_DOUBLE_EQ(got[k], want[k]) << what << " component " << k;
}

void expect_rotation(const tp::Mat3& want, const Matrix3& got, double tol) {
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(got[3 * r + c], want[r][c], tol) << "R(" << r << "," << c << ")";
}

}  // namespace

TEST(MessageRoundTrip, KinematicsFromTestPeerDecodeExactly) {
  std::mt19937 rng(42);
  for (const NodalConfig& c : all_configs()) {
    SCOPED_TRACE(c.describe());
    const tp::ElementShape shape = test::to_peer(c);
    const tp::NodeState ref = random_node(rng, 7);
    std::vector<tp::NodeState> nodes;
    for (std::uint32_t i = 0; i < c.num_points; ++i) nodes.push_back(random_node(rng, 100 + 3 * i));
    const auto payload = tp::encode_kinematics_payload(shape, ref, nodes);
    ASSERT_EQ(payload.size(), c.kinematics_payload_bytes());

    for (Command cmd : {Command::RegularData, Command::RegularDataAndGotoNextStep}) {
      std::vector<std::uint8_t> message{static_cast<std::uint8_t>(cmd)};
      message.insert(message.end(), payload.begin(), payload.end());
      const Kinematics k = decode_kinematics_message(c, message.data(), message.size());
      EXPECT_EQ(k.command, cmd);
      ASSERT_EQ(k.num_points(), c.num_points);
      const bool rot = c.has_rotation();
      // The orientation vector and Euler angles are recomputed by two different algorithms.
      const double rot_tol = c.rotation == Rotation::OrientationMatrix ? 0.0 : 1e-12;
      if (c.reference_node) {
        EXPECT_EQ(k.reference.label, c.labels ? 7u : 0u);
        expect_v3(ref.x, k.reference.x.data(), "ref x");
        expect_v3(ref.v, k.reference.v.data(), "ref v");
        if (rot) {
          expect_v3(ref.w, k.reference.omega.data(), "ref omega");
          expect_rotation(ref.R, k.reference_rotation_matrix(), rot_tol);
        }
        if (c.accelerations) expect_v3(ref.a, k.reference.a.data(), "ref a");
        if (c.accelerations && rot) expect_v3(ref.wdot, k.reference.omega_dot.data(), "ref omega_dot");
      }
      for (std::uint32_t i = 0; i < c.num_points; ++i) {
        if (c.labels) {
          EXPECT_EQ(k.labels[i], nodes[i].label);
        }
        expect_v3(nodes[i].x, &k.x[3 * i], "x");
        expect_v3(nodes[i].v, &k.v[3 * i], "v");
        if (rot) {
          expect_v3(nodes[i].w, &k.omega[3 * i], "omega");
          expect_rotation(nodes[i].R, k.rotation_matrix(i), rot_tol);
        } else {
          EXPECT_TRUE(k.omega.empty());
          expect_rotation(tp::Mat3{{{1, 0, 0}, {0, 1, 0}, {0, 0, 1}}}, k.rotation_matrix(i), 0.0);
        }
        if (c.accelerations) {
          expect_v3(nodes[i].a, &k.a[3 * i], "a");
        } else {
          EXPECT_TRUE(k.a.empty());
        }
        if (c.accelerations && rot) {
          expect_v3(nodes[i].wdot, &k.omega_dot[3 * i], "omega_dot");
        } else {
          EXPECT_TRUE(k.omega_dot.empty());
        }
      }
    }
  }
}

TEST(MessageRoundTrip, LoadsFromLibraryDecodeExactlyInTestPeer) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1e3, 1e3);
  for (const NodalConfig& c : all_configs()) {
    SCOPED_TRACE(c.describe());
    Loads loads(c);
    loads.reference_label = 9;
    loads.reference_force = {u(rng), u(rng), u(rng)};
    loads.reference_moment = {u(rng), u(rng), u(rng)};
    for (auto& l : loads.labels) l = static_cast<std::uint32_t>(rng());
    for (auto& f : loads.force) f = u(rng);
    for (auto& m : loads.moment) m = u(rng);
    for (Command cmd : {Command::RegularData, Command::RegularDataAndGotoNextStep}) {
      const auto bytes = encode_loads(c, cmd, loads);
      ASSERT_EQ(bytes.size(), 1 + c.loads_payload_bytes());
      EXPECT_EQ(bytes[0], static_cast<std::uint8_t>(cmd));
      const tp::LoadsMessage m = tp::decode_loads_payload(test::to_peer(c), bytes.data() + 1, bytes.size() - 1);
      if (c.reference_node) {
        if (c.labels) {
          EXPECT_EQ(m.ref_label, 9u);
        }
        expect_v3(tp::V3{loads.reference_force[0], loads.reference_force[1], loads.reference_force[2]},
                  m.ref_force.data(), "ref F");
        if (c.has_rotation())
          expect_v3(tp::V3{loads.reference_moment[0], loads.reference_moment[1], loads.reference_moment[2]},
                    m.ref_moment.data(), "ref M");
      }
      ASSERT_EQ(m.force.size(), c.num_points);
      for (std::uint32_t i = 0; i < c.num_points; ++i) {
        if (c.labels) {
          EXPECT_EQ(m.labels[i], loads.labels[i]);
        }
        expect_v3(m.force[i], &loads.force[3 * i], "F");
        if (c.has_rotation()) expect_v3(m.moment[i], &loads.moment[3 * i], "M");
      }
    }
  }
}

TEST(MessageRoundTrip, MatrixIsColumnMajorOnTheWire) {
  // spec §2: R11 R21 R31 R12 ... ; a rotation about z by 90 deg has R21 = +1, R12 = -1.
  NodalConfig c;
  c.num_points = 1;
  c.rotation = Rotation::OrientationMatrix;
  std::vector<double> wire(c.kinematics_payload_bytes() / 8, 0.0);
  const double col_major[9] = {0, 1, 0, -1, 0, 0, 0, 0, 1};
  std::copy(col_major, col_major + 9, wire.begin() + 3);
  const Kinematics k = decode_kinematics(c, Command::RegularDataAndGotoNextStep,
                                         reinterpret_cast<const std::uint8_t*>(wire.data()), wire.size() * 8);
  const Matrix3 R = k.rotation_matrix(0);
  EXPECT_EQ(R[3 * 1 + 0], 1.0);   // R21
  EXPECT_EQ(R[3 * 0 + 1], -1.0);  // R12
}

TEST(MessageRoundTrip, EulerAnglesAreDegreesAndVectorIsRadians) {
  // spec §4.3, verified: 0.05 rad about z = orientation vector (0,0,0.05) = euler (0,0,2.86479 deg).
  const double theta[3] = {0, 0, 0.05};
  const double euler[3] = {0, 0, 0.05 * 180.0 / 3.141592653589793};
  const Matrix3 a = matrix_from_orientation_vector(theta);
  const Matrix3 b = matrix_from_euler123_degrees(euler);
  for (int i = 0; i < 9; ++i) EXPECT_NEAR(a[i], b[i], 1e-15);
  EXPECT_NEAR(a[3 * 1 + 0], std::sin(0.05), 1e-15);
}

TEST(MessageRoundTrip, EncodeLoadsRejectsWrongSizesAndNonFinite) {
  NodalConfig c;
  c.num_points = 2;
  Loads loads(c);
  loads.force.pop_back();
  EXPECT_THROW(encode_loads(c, Command::RegularDataAndGotoNextStep, loads), std::invalid_argument);
  Loads nan_loads(c);
  nan_loads.moment[4] = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(encode_loads(c, Command::RegularDataAndGotoNextStep, nan_loads), MalformedMessageError);
  EXPECT_THROW(encode_loads(c, Command::GotoNextStep, Loads(c)), std::invalid_argument);
}

TEST(MessageRoundTrip, HugeOrientationVectorStillGivesARotation) {
  // Regression (found by the fuzzer): |theta|^2 overflowed and the matrix became NaN.
  const double theta[3] = {3e281, 3e281, 3e281};
  const Matrix3 R = matrix_from_orientation_vector(theta);
  for (int a = 0; a < 3; ++a)
    for (int b = 0; b < 3; ++b) {
      double dot = 0;
      for (int j = 0; j < 3; ++j) dot += R[3 * j + a] * R[3 * j + b];
      EXPECT_NEAR(dot, a == b ? 1.0 : 0.0, 1e-12);
    }
  // And the small-angle branch joins the exact formula continuously.
  const double n[3] = {0.6 / 0.877496, -0.5 / 0.877496, 0.4 / 0.877496};
  double below[3], above[3];
  for (int k = 0; k < 3; ++k) {
    below[k] = n[k] * 0.99999e-6;
    above[k] = n[k] * 1.00001e-6;
  }
  const Matrix3 A = matrix_from_orientation_vector(below), B = matrix_from_orientation_vector(above);
  EXPECT_NEAR(A[3 * 1 + 0], n[2] * 1e-6, 1e-10);  // R21 = sin(a) n_z
  for (int i = 0; i < 9; ++i) EXPECT_NEAR(A[i], B[i], 1e-10);
}
