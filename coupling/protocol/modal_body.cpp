#include "modal_body.h"

#include "math/rotation.h"

#include <cmath>
#include <sstream>
#include <stdexcept>

namespace dembridge::mbdyn {

namespace {

using V3 = math::Vec3;
// R a, Rᵀ a and a × b from the math layer (R row-major, sums in index order)
V3 mul(const Matrix3& R, const V3& a) { return math::mat_vec(R, a.data()); }
V3 mul_transposed(const Matrix3& R, const V3& a) { return math::mat_t_vec(R, a.data()); }
using math::cross;

void check_modes(const ModalBody& body, const ModalKinematics& k) {
  if (k.q.size() != body.num_modes || k.qdot.size() != body.num_modes)
    throw std::invalid_argument("modal body: expected " + std::to_string(body.num_modes) +
                                " modal coordinates, the message has " + std::to_string(k.q.size()));
}

}  // namespace

FemModel select_modes(const FemModel& fem, std::size_t element_modes, const std::vector<int>& modes_1based) {
  std::vector<int> list = modes_1based;
  if (list.empty())
    for (std::size_t m = 1; m <= element_modes; ++m) list.push_back(static_cast<int>(m));
  if (list.size() != element_modes)
    throw std::invalid_argument("expected " + std::to_string(element_modes) + " modes in the mode list, got " +
                                std::to_string(list.size()));
  std::vector<bool> used(fem.num_modes + 1, false);
  for (int m : list) {
    if (m < 1 || static_cast<std::size_t>(m) > fem.num_modes)
      throw std::invalid_argument("mode " + std::to_string(m) + " is not in FEM file '" + fem.path + "', which has " +
                                  std::to_string(fem.num_modes) + " modes");
    if (used[m]) throw std::invalid_argument("mode " + std::to_string(m) + " listed twice");
    used[m] = true;
  }
  FemModel out = fem;
  out.num_modes = list.size();
  out.shapes.clear();
  out.q0.clear();
  out.qdot0.clear();
  const std::size_t per_mode = 6 * fem.num_nodes();
  for (int m : list) {
    out.shapes.insert(out.shapes.end(), fem.shapes.begin() + (m - 1) * per_mode, fem.shapes.begin() + m * per_mode);
    out.q0.push_back(fem.q0[m - 1]);
    out.qdot0.push_back(fem.qdot0[m - 1]);
  }
  auto sub = [&](const std::vector<double>& a) {
    std::vector<double> b;
    if (a.empty()) return b;
    for (int i : list)
      for (int j : list) b.push_back(a[(i - 1) * fem.num_modes + (j - 1)]);
    return b;
  };
  out.mass = sub(fem.mass);
  out.stiffness = sub(fem.stiffness);
  out.damping = sub(fem.damping);
  return out;
}

ModalBody map_points_to_fem_nodes(const FemModel& fem, const std::vector<std::array<double, 3>>& points,
                                  const std::string& origin_label, double tolerance) {
  V3 origin{0.0, 0.0, 0.0};
  if (!origin_label.empty()) origin = fem.node_xyz[fem.node_index(origin_label)];
  ModalBody body;
  body.num_modes = fem.num_modes;
  for (std::size_t v = 0; v < points.size(); ++v) {
    std::size_t best = 0;
    double best_d = INFINITY;
    for (std::size_t n = 0; n < fem.num_nodes(); ++n) {
      const double d = std::hypot(points[v][0] - fem.node_xyz[n][0], points[v][1] - fem.node_xyz[n][1],
                                  points[v][2] - fem.node_xyz[n][2]);
      if (d < best_d) best_d = d, best = n;
    }
    if (!(best_d <= tolerance)) {
      std::ostringstream msg;
      msg << "point " << v + 1 << " at (" << points[v][0] << ", " << points[v][1] << ", " << points[v][2]
          << ") is " << best_d << " from the nearest FEM node '" << fem.node_labels[best] << "' of '" << fem.path
          << "', expected at most " << tolerance;
      throw std::invalid_argument(msg.str());
    }
    body.fem_node.push_back(best);
    body.rest.push_back({points[v][0] - origin[0], points[v][1] - origin[1], points[v][2] - origin[2]});
  }
  const std::size_t P = points.size();
  body.shapes.assign(fem.num_modes * P * 3, 0.0);
  for (std::size_t m = 0; m < fem.num_modes; ++m)
    for (std::size_t v = 0; v < P; ++v) {
      const V3 s = fem.translation(m, body.fem_node[v]);
      for (int k = 0; k < 3; ++k) body.shapes[(m * P + v) * 3 + k] = s[k];
    }
  return body;
}

void modal_point_states(const ModalBody& body, const ModalKinematics& k, std::vector<double>& x,
                        std::vector<double>& v) {
  check_modes(body, k);
  const std::size_t P = body.num_points();
  x.resize(3 * P);
  v.resize(3 * P);
  for (std::size_t p = 0; p < P; ++p) {
    V3 d = body.rest[p], dd{0.0, 0.0, 0.0};
    for (std::size_t m = 0; m < body.num_modes; ++m)
      for (int c = 0; c < 3; ++c) {
        const double phi = body.shapes[(m * P + p) * 3 + c];
        d[c] += k.q[m] * phi;
        dd[c] += k.qdot[m] * phi;
      }
    const V3 r = mul(k.R, d), rd = mul(k.R, dd), w = cross(k.omega, r);
    for (int c = 0; c < 3; ++c) {
      x[3 * p + c] = k.x[c] + r[c];
      v[3 * p + c] = k.v[c] + w[c] + rd[c];
    }
  }
}

ModalLoads project_modal_loads(const ModalBody& body, const ModalKinematics& k, const std::vector<double>& x,
                               const std::vector<double>& f) {
  const std::size_t P = body.num_points();
  if (x.size() != 3 * P || f.size() != 3 * P)
    throw std::invalid_argument("modal body: expected 3 x " + std::to_string(P) + " positions and forces");
  ModalLoads l;
  l.p.assign(body.num_modes, 0.0);
  for (std::size_t p = 0; p < P; ++p) {
    const V3 fv{f[3 * p], f[3 * p + 1], f[3 * p + 2]};
    const V3 arm{x[3 * p] - k.x[0], x[3 * p + 1] - k.x[1], x[3 * p + 2] - k.x[2]};
    const V3 m = cross(arm, fv), local = mul_transposed(k.R, fv);
    for (int c = 0; c < 3; ++c) {
      l.force[c] += fv[c];
      l.moment[c] += m[c];
    }
    for (std::size_t mode = 0; mode < body.num_modes; ++mode)
      for (int c = 0; c < 3; ++c) l.p[mode] += body.shapes[(mode * P + p) * 3 + c] * local[c];
  }
  return l;
}

}  // namespace dembridge::mbdyn
