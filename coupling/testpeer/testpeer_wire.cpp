#include "testpeer_wire.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <string>

namespace dembridge::mbdyn::testpeer {

namespace {

constexpr double kPi = 3.141592653589793238462643383279502884;

struct ByteSink {
  std::vector<std::uint8_t> bytes;
  template <class T>
  void put(T value) {
    std::uint8_t raw[sizeof(T)];
    std::memcpy(raw, &value, sizeof(T));
    bytes.insert(bytes.end(), raw, raw + sizeof(T));
  }
  void put3(const V3& v) {
    for (double d : v) put(d);
  }
};

bool rotates(const ElementShape& s) { return s.orientation != Orientation::None; }

void put_orientation(ByteSink& out, Orientation o, const Mat3& R) {
  switch (o) {
    case Orientation::None: return;
    case Orientation::Matrix:
      // Column by column: R11 R21 R31 R12 ... (spec §2; the file format would be row-wise).
      for (int col = 0; col < 3; ++col)
        for (int row = 0; row < 3; ++row) out.put(R[row][col]);
      return;
    case Orientation::Vector: out.put3(rotation_vector_of(R)); return;
    case Orientation::Euler123: out.put3(euler123_degrees_of(R)); return;
  }
}

}  // namespace

const char* orientation_keyword(Orientation o) {
  switch (o) {
    case Orientation::None: return "none";
    case Orientation::Vector: return "orientation vector";
    case Orientation::Matrix: return "orientation matrix";
    case Orientation::Euler123: return "euler 123";
  }
  return "?";
}

std::uint32_t negotiation_flags(const ElementShape& s) {
  std::uint32_t f = 0x2;  // MBC_NODAL
  if (s.reference_node) f |= 0x4;
  if (s.accelerations) f |= 0x8;
  if (s.labels) f |= 0x10;
  switch (s.orientation) {
    case Orientation::None: break;
    case Orientation::Vector: f |= 0x100; break;
    case Orientation::Matrix: f |= 0x200; break;
    case Orientation::Euler123: f |= 0x400; break;
  }
  return f;
}

std::vector<std::uint8_t> encode_kinematics_payload(const ElementShape& s, const NodeState& ref,
                                                    const std::vector<NodeState>& nodes) {
  ByteSink out;
  const bool rot = rotates(s);
  if (s.reference_node) {
    if (s.labels) {
      out.put<std::uint32_t>(ref.label);
      out.put<std::uint32_t>(0);
    }
    out.put3(ref.x);
    put_orientation(out, s.orientation, ref.R);
    out.put3(ref.v);
    if (rot) out.put3(ref.w);
    if (s.accelerations) {
      out.put3(ref.a);
      if (rot) out.put3(ref.wdot);
    }
  }
  if (!nodes.empty()) {
    if (s.labels) {
      for (const NodeState& n : nodes) out.put<std::uint32_t>(n.label);
      if (nodes.size() % 2 == 1) out.put<std::uint32_t>(0);
    }
    // Structure of arrays: all x, then all orientations, ... (spec §2).
    for (const NodeState& n : nodes) out.put3(n.x);
    for (const NodeState& n : nodes) put_orientation(out, s.orientation, n.R);
    for (const NodeState& n : nodes) out.put3(n.v);
    if (rot)
      for (const NodeState& n : nodes) out.put3(n.w);
    if (s.accelerations) {
      for (const NodeState& n : nodes) out.put3(n.a);
      if (rot)
        for (const NodeState& n : nodes) out.put3(n.wdot);
    }
  }
  return out.bytes;
}

std::size_t loads_payload_size(const ElementShape& s) {
  const std::size_t per = rotates(s) ? 6 : 3;
  std::size_t size = 0;
  if (s.reference_node) size += (s.labels ? 8 : 0) + 8 * per;
  if (s.nodes > 0) size += (s.labels ? 4 * (s.nodes + s.nodes % 2) : 0) + 8 * per * s.nodes;
  return size;
}

LoadsMessage decode_loads_payload(const ElementShape& s, const std::uint8_t* data, std::size_t size) {
  if (size != loads_payload_size(s))
    throw std::runtime_error("loads payload of " + std::to_string(size) + " bytes, expected " +
                             std::to_string(loads_payload_size(s)));
  std::size_t at = 0;
  auto get_u32 = [&]() {
    std::uint32_t v;
    std::memcpy(&v, data + at, 4);
    at += 4;
    return v;
  };
  auto get_v3 = [&]() {
    V3 v;
    std::memcpy(v.data(), data + at, 24);
    at += 24;
    return v;
  };
  LoadsMessage m;
  const bool rot = rotates(s);
  if (s.reference_node) {
    if (s.labels) {
      m.ref_label = get_u32();
      get_u32();
    }
    m.ref_force = get_v3();
    if (rot) m.ref_moment = get_v3();
  }
  if (s.nodes > 0) {
    if (s.labels) {
      for (std::uint32_t i = 0; i < s.nodes; ++i) m.labels.push_back(get_u32());
      if (s.nodes % 2) get_u32();
    }
    for (std::uint32_t i = 0; i < s.nodes; ++i) m.force.push_back(get_v3());
    for (std::uint32_t i = 0; i < s.nodes; ++i) m.moment.push_back(rot ? get_v3() : V3{0, 0, 0});
  }
  return m;
}

V3 rotation_vector_of(const Mat3& R) {
  // Via the quaternion (Shepperd), robust for all angles below pi.
  const double tr = R[0][0] + R[1][1] + R[2][2];
  double w, x, y, z;
  if (tr > 0) {
    const double s = 2.0 * std::sqrt(1.0 + tr);
    w = 0.25 * s;
    x = (R[2][1] - R[1][2]) / s;
    y = (R[0][2] - R[2][0]) / s;
    z = (R[1][0] - R[0][1]) / s;
  } else if (R[0][0] > R[1][1] && R[0][0] > R[2][2]) {
    const double s = 2.0 * std::sqrt(1.0 + R[0][0] - R[1][1] - R[2][2]);
    w = (R[2][1] - R[1][2]) / s;
    x = 0.25 * s;
    y = (R[0][1] + R[1][0]) / s;
    z = (R[0][2] + R[2][0]) / s;
  } else if (R[1][1] > R[2][2]) {
    const double s = 2.0 * std::sqrt(1.0 + R[1][1] - R[0][0] - R[2][2]);
    w = (R[0][2] - R[2][0]) / s;
    x = (R[0][1] + R[1][0]) / s;
    y = 0.25 * s;
    z = (R[1][2] + R[2][1]) / s;
  } else {
    const double s = 2.0 * std::sqrt(1.0 + R[2][2] - R[0][0] - R[1][1]);
    w = (R[1][0] - R[0][1]) / s;
    x = (R[0][2] + R[2][0]) / s;
    y = (R[1][2] + R[2][1]) / s;
    z = 0.25 * s;
  }
  if (w < 0) {
    w = -w;
    x = -x;
    y = -y;
    z = -z;
  }
  const double sn = std::sqrt(x * x + y * y + z * z);
  if (sn < 1e-300) return {0, 0, 0};
  const double angle = 2.0 * std::atan2(sn, w);
  return {angle * x / sn, angle * y / sn, angle * z / sn};
}

V3 euler123_degrees_of(const Mat3& R) {
  // R = Rx(a) Ry(b) Rz(c): R[0][2] = sin b, R[1][2] = -sin a cos b, R[0][1] = -cos b sin c.
  const double deg = 180.0 / kPi;
  const double b = std::asin(std::max(-1.0, std::min(1.0, R[0][2])));
  const double a = std::atan2(-R[1][2], R[2][2]);
  const double c = std::atan2(-R[0][1], R[0][0]);
  return {a * deg, b * deg, c * deg};
}

Mat3 rotation_about_z(double t) {
  const double c = std::cos(t), s = std::sin(t);
  return Mat3{{{c, -s, 0}, {s, c, 0}, {0, 0, 1}}};
}
Mat3 rotation_about_x(double t) {
  const double c = std::cos(t), s = std::sin(t);
  return Mat3{{{1, 0, 0}, {0, c, -s}, {0, s, c}}};
}
Mat3 rotation_about_y(double t) {
  const double c = std::cos(t), s = std::sin(t);
  return Mat3{{{c, 0, s}, {0, 1, 0}, {-s, 0, c}}};
}

Mat3 multiply(const Mat3& A, const Mat3& B) {
  Mat3 C{};
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      for (int k = 0; k < 3; ++k) C[i][j] += A[i][k] * B[k][j];
  return C;
}

Mat3 transpose(const Mat3& A) {
  Mat3 T{};
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) T[i][j] = A[j][i];
  return T;
}

V3 rotate_vector(const Mat3& A, const V3& v) {
  V3 r{};
  for (int i = 0; i < 3; ++i)
    for (int k = 0; k < 3; ++k) r[i] += A[i][k] * v[k];
  return r;
}

}  // namespace dembridge::mbdyn::testpeer
