// A body on MBDyn's modal node deformed by its modes (the recorded run's body.fem: 3 FEM nodes
// on the x axis, mode 1 along z and mode 2 along y with nodal shape (1, -2, 1)): point motion
// and the answer's generalized forces against closed forms.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "modal_body.h"

using namespace dembridge::mbdyn;

namespace {

const std::string kBody = std::string(DEMBRIDGE_MBDYN_EXT_DATA) + "/modal_body/body.fem";
const std::vector<std::array<double, 3>> kNodes{{0, 0, 0}, {0.5, 0, 0}, {1, 0, 0}};

// A rotation of 90 degrees about x: R^T (a, b, c) = (a, c, -b).
ModalKinematics rotated_about_x(std::vector<double> q, std::vector<double> qdot) {
  ModalKinematics k;
  k.x = {0.3, -0.2, 0.1};
  k.R = {1, 0, 0, 0, 0, -1, 0, 1, 0};
  k.v = {0.01, 0.02, 0.03};
  k.omega = {0.0, 0.0, 0.2};
  k.q = std::move(q);
  k.qdot = std::move(qdot);
  return k;
}

ModalBody body_on_fem_nodes() {
  const FemModel fem = select_modes(read_fem_file(kBody), 2, {});
  return map_points_to_fem_nodes(fem, kNodes, "1", 1e-12);
}

}  // namespace

TEST(ModalBody, PointsMoveByRotatedModalDisplacement) {
  const ModalBody body = body_on_fem_nodes();
  const ModalKinematics k = rotated_about_x({0.02, -0.01}, {0.3, 0.4});
  std::vector<double> x, v;
  modal_point_states(body, k, x, v);
  const double w[3] = {1.0, -2.0, 1.0};
  for (int p = 0; p < 3; ++p) {
    // closed form: the modal displacement (0, -0.01 w, 0.02 w) rotated: (0, -0.02 w, -0.01 w)
    const double rest_x = 0.5 * p;
    const double expect[3] = {0.3 + rest_x, -0.2 - 0.02 * w[p], 0.1 - 0.01 * w[p]};
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(x[3 * p + c], expect[c], 1e-16) << p << c;
    // v = v_n + omega x (x - x_n) + R (0, 0.4 w, 0.3 w), R (0, a, b) = (0, -b, a)
    const double arm[3] = {rest_x, -0.02 * w[p], -0.01 * w[p]};
    const double vexp[3] = {0.01 - 0.2 * arm[1], 0.02 + 0.2 * arm[0] - 0.3 * w[p], 0.03 + 0.4 * w[p]};
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(v[3 * p + c], vexp[c], 1e-16) << p << c;
  }
}

TEST(ModalBody, GeneralizedForcesAreShapesDotLocalForces) {
  const ModalBody body = body_on_fem_nodes();
  const ModalKinematics k = rotated_about_x({0.02, -0.01}, {0.0, 0.0});
  std::vector<double> x, v;
  modal_point_states(body, k, x, v);
  const std::vector<double> f{1.0, 2.0, 3.0, -0.5, 0.25, 4.0, 0.75, -1.5, -2.0};
  const ModalLoads l = project_modal_loads(body, k, x, f);
  // R^T f = (a, c, -b): mode 1 (z shape w) takes -b, mode 2 (y shape w) takes c
  EXPECT_NEAR(l.p[0], -(1.0 * 2.0 - 2.0 * 0.25 + 1.0 * -1.5), 1e-15);
  EXPECT_NEAR(l.p[1], 1.0 * 3.0 - 2.0 * 4.0 + 1.0 * -2.0, 1e-15);
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(l.force[c], f[c] + f[3 + c] + f[6 + c], 1e-15);
  double m[3] = {0, 0, 0};
  for (int p = 0; p < 3; ++p) {
    const double r[3] = {x[3 * p] - 0.3, x[3 * p + 1] + 0.2, x[3 * p + 2] - 0.1};
    const double* fp = &f[3 * p];
    m[0] += r[1] * fp[2] - r[2] * fp[1];
    m[1] += r[2] * fp[0] - r[0] * fp[2];
    m[2] += r[0] * fp[1] - r[1] * fp[0];
  }
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(l.moment[c], m[c], 1e-15);
  // virtual work: p . dq equals the work of f over the point displacement dx = R Phi dq
  const double dq[2] = {1e-3, -2e-3};
  ModalKinematics k2 = k;
  k2.q = {k.q[0] + dq[0], k.q[1] + dq[1]};
  std::vector<double> x2, v2;
  modal_point_states(body, k2, x2, v2);
  double work = 0.0;
  for (int i = 0; i < 9; ++i) work += f[i] * (x2[i] - x[i]);
  EXPECT_NEAR(l.p[0] * dq[0] + l.p[1] * dq[1], work, 1e-15);
}

TEST(ModalBody, ModeListAndOrigin) {
  const FemModel fem = read_fem_file(kBody);
  const FemModel second = select_modes(fem, 1, {2});
  EXPECT_EQ(second.num_modes, 1u);
  EXPECT_EQ(second.translation(0, 1), (std::array<double, 3>{0.0, -2.0, 0.0}));
  EXPECT_EQ(second.stiffness, (std::vector<double>{1350.0}));
  const ModalBody b = map_points_to_fem_nodes(second, {{1.0, 0.0, 0.0}}, "2", 1e-9);
  EXPECT_EQ(b.rest[0], (std::array<double, 3>{0.5, 0.0, 0.0}));
  EXPECT_EQ(b.fem_node[0], 2u);
}

TEST(ModalBody, BadInputRefused) {
  const FemModel fem = read_fem_file(kBody);
  auto expect = [](auto&& call, const std::string& part) {
    try {
      call();
      ADD_FAILURE() << "accepted, expected: " << part;
    } catch (const std::exception& e) {
      EXPECT_NE(std::string(e.what()).find(part), std::string::npos) << e.what();
    }
  };
  // the element has more modes than the FEM file
  expect([&] { select_modes(fem, 3, {}); }, "mode 3 is not in FEM file");
  expect([&] { select_modes(fem, 2, {1, 1}); }, "mode 1 listed twice");
  expect([&] { select_modes(fem, 2, {2}); }, "expected 2 modes in the mode list, got 1");
  // a point on no FEM node
  expect([&] { map_points_to_fem_nodes(fem, {{0.25, 0.0, 0.0}}, "1", 1e-6); },
         "point 1 at (0.25, 0, 0) is 0.25 from the nearest FEM node");
  expect([&] { map_points_to_fem_nodes(fem, kNodes, "7", 1e-6); }, "no FEM node labelled '7'");
  // a message with other modes than the body
  const ModalBody body = map_points_to_fem_nodes(fem, kNodes, "1", 1e-12);
  std::vector<double> x, v;
  expect([&] { modal_point_states(body, rotated_about_x({0.1}, {0.0}), x, v); },
         "expected 2 modal coordinates, the message has 1");
  expect([&] { project_modal_loads(body, rotated_about_x({0, 0}, {0, 0}), std::vector<double>(9), std::vector<double>(6)); },
         "expected 3 x 3 positions and forces");
}
