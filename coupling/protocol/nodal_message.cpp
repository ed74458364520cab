#include "nodal_message.h"

#include <cmath>
#include <cstring>
#if defined(__SSE2__)
#include <emmintrin.h>
#endif
#include <sstream>
#include <stdexcept>
#include <string>

#include "protocol_error.h"

namespace dembridge::mbdyn {

namespace {

// Sequential reader over a payload; memcpy because the payload need not be aligned (spec P6).
class PayloadReader {
 public:
  PayloadReader(const std::uint8_t* data, std::size_t size) : data_(data), size_(size) {}
  std::uint32_t u32() {
    std::uint32_t v;
    std::memcpy(&v, take(4), 4);
    return v;
  }
  void doubles(double* out, std::size_t n) { std::memcpy(out, take(8 * n), 8 * n); }
  void skip(std::size_t n) { take(n); }
  std::size_t offset() const { return offset_; }

 private:
  const std::uint8_t* take(std::size_t n) {
    // Lengths are checked before decoding; this guards the arithmetic itself.
    if (n > size_ - offset_) throw std::logic_error("PayloadReader: read past the checked size");
    const std::uint8_t* p = data_ + offset_;
    offset_ += n;
    return p;
  }
  const std::uint8_t* data_;
  std::size_t size_;
  std::size_t offset_ = 0;
};

// Sequential writer into a buffer sized beforehand (plain stores, no growth checks per field).
class PayloadWriter {
 public:
  explicit PayloadWriter(std::vector<std::uint8_t>& out) : out_(out) {}
  void u8(std::uint8_t v) { append(&v, 1); }
  void u32(std::uint32_t v) { append(&v, 4); }
  void doubles(const double* v, std::size_t n) { append(v, 8 * n); }
  std::size_t offset() const { return offset_; }

 private:
  void append(const void* p, std::size_t n) {
    if (n > out_.size() - offset_) throw std::logic_error("PayloadWriter: write past the buffer");
    if (n) std::memcpy(out_.data() + offset_, p, n);
    offset_ += n;
  }
  std::vector<std::uint8_t>& out_;
  std::size_t offset_ = 0;
};

// True when no value is inf or NaN: v * 0 is 0 for finite v and NaN otherwise, and a NaN
// survives any sum. Two lanes at a time where SSE2 exists; the per-value search below runs only
// to name a bad value.
bool all_finite(const double* v, std::size_t n) {
  std::size_t i = 0;
#if defined(__SSE2__)
  __m128d s0 = _mm_setzero_pd(), s1 = _mm_setzero_pd();
  const __m128d zero = _mm_setzero_pd();
  for (; i + 4 <= n; i += 4) {
    s0 = _mm_add_pd(s0, _mm_mul_pd(_mm_loadu_pd(v + i), zero));
    s1 = _mm_add_pd(s1, _mm_mul_pd(_mm_loadu_pd(v + i + 2), zero));
  }
  double lanes[2];
  _mm_storeu_pd(lanes, _mm_add_pd(s0, s1));
  double sum = lanes[0] + lanes[1];
#else
  double sum = 0.0;
#endif
  for (; i < n; ++i) sum += v[i] * 0.0;
  return sum == 0.0;
}

void require_finite(const double* values, std::size_t per_point, std::size_t points,
                    const char* field, const std::vector<std::uint32_t>& labels) {
  if (all_finite(values, per_point * points)) return;
  for (std::size_t i = 0; i < points; ++i)
    for (std::size_t k = 0; k < per_point; ++k) {
      const double value = values[i * per_point + k];
      if (std::isfinite(value)) continue;
      std::ostringstream msg;
      msg << "MBDyn kinematics: expected finite values, received " << value << " in field '"
          << field << "' of point " << i;
      if (!labels.empty()) msg << " (label " << labels[i] << ")";
      msg << ", component " << k;
      throw MalformedMessageError(msg.str());
    }
}

void read_vectors(PayloadReader& r, std::vector<double>& out, std::size_t per_point,
                  std::size_t points, bool present) {
  if (!present) {
    out.clear();
    return;
  }
  out.resize(per_point * points);  // the same size as the last message: no allocation, no zero fill
  r.doubles(out.data(), out.size());
}

}  // namespace

Matrix3 matrix_from_orientation_vector(const double* t) {
  // Rodrigues with the unit axis n = t / a: R = I + sin(a) [n]x + (1 - cos(a)) [n]x^2.
  // Normalising first keeps every term finite even for huge angles (found by the fuzzer:
  // a^2 overflowed to inf and gave NaN); below 1e-6 rad the series of sin(a)/a is used.
  const double a = std::hypot(t[0], t[1], t[2]);
  double x, y, z, s, c;
  if (a < 1e-6) {
    const double a2 = a * a;
    x = t[0];
    y = t[1];
    z = t[2];
    s = 1.0 - a2 / 6.0;   // sin(a) / a, multiplies the unnormalised t
    c = 0.5 - a2 / 24.0;  // (1 - cos(a)) / a^2
  } else {
    x = t[0] / a;
    y = t[1] / a;
    z = t[2] / a;
    s = std::sin(a);
    c = 1.0 - std::cos(a);
  }
  return {1.0 - c * (y * y + z * z), -s * z + c * x * y, s * y + c * x * z,
          s * z + c * x * y, 1.0 - c * (x * x + z * z), -s * x + c * y * z,
          -s * y + c * x * z, s * x + c * y * z, 1.0 - c * (x * x + y * y)};
}

Matrix3 matrix_from_euler123_degrees(const double* e) {
  const double k = 3.14159265358979323846 / 180.0;
  const double c1 = std::cos(e[0] * k), s1 = std::sin(e[0] * k);
  const double c2 = std::cos(e[1] * k), s2 = std::sin(e[1] * k);
  const double c3 = std::cos(e[2] * k), s3 = std::sin(e[2] * k);
  // Rx(e1) * Ry(e2) * Rz(e3) (spec §4.3, verified).
  return {c2 * c3, -c2 * s3, s2,
          c1 * s3 + s1 * s2 * c3, c1 * c3 - s1 * s2 * s3, -s1 * c2,
          s1 * s3 - c1 * s2 * c3, s1 * c3 + c1 * s2 * s3, c1 * c2};
}

namespace {
Matrix3 matrix_from_wire(Rotation rotation, const double* values) {
  switch (rotation) {
    case Rotation::None: break;
    case Rotation::OrientationMatrix: return matrix_from_wire_column_major(values);
    case Rotation::OrientationVector: return matrix_from_orientation_vector(values);
    case Rotation::Euler123: return matrix_from_euler123_degrees(values);
  }
  return {1, 0, 0, 0, 1, 0, 0, 0, 1};
}
}  // namespace

Matrix3 Kinematics::rotation_matrix(std::size_t i) const {
  if (rotation == Rotation::None) return matrix_from_wire(rotation, nullptr);
  return matrix_from_wire(rotation, &orientation.at(rotation_doubles(rotation) * i));
}

Matrix3 Kinematics::reference_rotation_matrix() const {
  return matrix_from_wire(rotation, reference.orientation.data());
}

Loads::Loads(const NodalConfig& config)
    : labels(config.labels ? config.num_points : 0, 0u),
      force(3 * static_cast<std::size_t>(config.num_points), 0.0),
      moment(config.has_rotation() ? 3 * static_cast<std::size_t>(config.num_points) : 0, 0.0) {}

void Loads::set_force(std::size_t i, const Vec3& f) {
  for (int k = 0; k < 3; ++k) force.at(3 * i + k) = f[k];
}

void Loads::set_moment(std::size_t i, const Vec3& m) {
  for (int k = 0; k < 3; ++k) moment.at(3 * i + k) = m[k];
}

Kinematics decode_kinematics(const NodalConfig& config, Command command,
                             const std::uint8_t* payload, std::size_t size) {
  Kinematics k;
  decode_kinematics_into(config, command, payload, size, k);
  return k;
}

void decode_kinematics_into(const NodalConfig& config, Command command, const std::uint8_t* payload,
                            std::size_t size, Kinematics& k) {
  const std::size_t expected = config.kinematics_payload_bytes();
  if (size != expected) {
    std::ostringstream msg;
    msg << "MBDyn kinematics: expected a payload of " << expected << " bytes for "
        << config.describe() << ", received " << size << " bytes";
    throw MalformedMessageError(msg.str());
  }
  const std::size_t n = config.num_points;
  const std::size_t nr = config.rotation_doubles();
  const bool rot = config.has_rotation();
  const bool acc = config.accelerations;

  // k's vectors keep their capacity from message to message (no allocation, no zero fill); the
  // fields this layout lacks are emptied, as in a fresh Kinematics.
  k.command = command;
  k.rotation = config.rotation;
  k.has_reference = config.reference_node;
  k.reference = ReferenceKinematics{};
  if (!config.labels) k.labels.clear();
  PayloadReader r(payload, size);

  if (config.reference_node) {
    ReferenceKinematics& ref = k.reference;
    if (config.labels) {
      ref.label = r.u32();
      r.skip(4);  // pad, ignored on receipt (spec §2)
    }
    r.doubles(ref.x.data(), 3);
    if (rot) r.doubles(ref.orientation.data(), nr);
    r.doubles(ref.v.data(), 3);
    if (rot) r.doubles(ref.omega.data(), 3);
    if (acc) r.doubles(ref.a.data(), 3);
    if (acc && rot) r.doubles(ref.omega_dot.data(), 3);
    const std::vector<std::uint32_t> no_labels;
    const std::vector<std::uint32_t> ref_labels{ref.label};
    const auto& lab = config.labels ? ref_labels : no_labels;
    require_finite(ref.x.data(), 3, 1, "reference x", lab);
    require_finite(ref.orientation.data(), nr, 1, "reference orientation", lab);
    require_finite(ref.v.data(), 3, 1, "reference v", lab);
    require_finite(ref.omega.data(), 3, 1, "reference omega", lab);
    require_finite(ref.a.data(), 3, 1, "reference a", lab);
    require_finite(ref.omega_dot.data(), 3, 1, "reference omega_dot", lab);
  }

  if (n > 0) {
    if (config.labels) {
      k.labels.resize(n);
      for (auto& l : k.labels) l = r.u32();
      if (n % 2) r.skip(4);
    }
    read_vectors(r, k.x, 3, n, true);
    read_vectors(r, k.orientation, nr, n, rot);
    read_vectors(r, k.v, 3, n, true);
    read_vectors(r, k.omega, 3, n, rot);
    read_vectors(r, k.a, 3, n, acc);
    read_vectors(r, k.omega_dot, 3, n, acc && rot);
    require_finite(k.x.data(), 3, n, "x", k.labels);
    require_finite(k.orientation.data(), nr, rot ? n : 0, "orientation", k.labels);
    require_finite(k.v.data(), 3, n, "v", k.labels);
    require_finite(k.omega.data(), 3, rot ? n : 0, "omega", k.labels);
    require_finite(k.a.data(), 3, acc ? n : 0, "a", k.labels);
    require_finite(k.omega_dot.data(), 3, (acc && rot) ? n : 0, "omega_dot", k.labels);
  } else {  // no points: empty, as in a fresh Kinematics
    k.labels.clear();
    for (std::vector<double>* v : {&k.x, &k.orientation, &k.v, &k.omega, &k.a, &k.omega_dot}) v->clear();
  }
  if (r.offset() != size) throw std::logic_error("decode_kinematics: layout and size disagree");
}

Kinematics decode_kinematics_message(const NodalConfig& config, const std::uint8_t* bytes,
                                     std::size_t size) {
  if (size < 1) throw MalformedMessageError("MBDyn kinematics: expected a command byte, received 0 bytes");
  const std::uint8_t cmd = bytes[0];
  if (cmd != static_cast<std::uint8_t>(Command::RegularData) &&
      cmd != static_cast<std::uint8_t>(Command::RegularDataAndGotoNextStep))
    throw MalformedMessageError("MBDyn kinematics: expected command 2 or 6, received " +
                                command_name(cmd));
  return decode_kinematics(config, static_cast<Command>(cmd), bytes + 1, size - 1);
}

std::vector<std::uint8_t> encode_loads(const NodalConfig& config, Command command,
                                       const Loads& loads) {
  std::vector<std::uint8_t> out;
  encode_loads_into(config, command, loads, out);
  return out;
}

void encode_loads_into(const NodalConfig& config, Command command, const Loads& loads,
                       std::vector<std::uint8_t>& out) {
  if (command != Command::RegularData && command != Command::RegularDataAndGotoNextStep)
    throw std::invalid_argument("encode_loads: a payload follows only commands 2 and 6, not " +
                                command_name(static_cast<std::uint8_t>(command)));
  const std::size_t n = config.num_points;
  const bool rot = config.has_rotation();
  auto size_error = [&](const char* what, std::size_t got, std::size_t want) {
    std::ostringstream msg;
    msg << "encode_loads: " << what << " has " << got << " values, expected " << want << " for "
        << config.describe();
    throw std::invalid_argument(msg.str());
  };
  if (loads.force.size() != 3 * n) size_error("force", loads.force.size(), 3 * n);
  if (rot && loads.moment.size() != 3 * n) size_error("moment", loads.moment.size(), 3 * n);
  if (config.labels && loads.labels.size() != n) size_error("labels", loads.labels.size(), n);
  auto check_finite = [](const double* v, std::size_t count, const char* what) {
    if (all_finite(v, count)) return;
    for (std::size_t i = 0; i < count; ++i)
      if (!std::isfinite(v[i])) {
        std::ostringstream msg;
        msg << "loads for MBDyn: expected finite values, " << what << " of point " << i / 3
            << " component " << i % 3 << " is " << v[i];
        throw MalformedMessageError(msg.str());
      }
  };
  check_finite(loads.force.data(), 3 * n, "force");
  if (rot) check_finite(loads.moment.data(), 3 * n, "moment");
  if (config.reference_node) {
    check_finite(loads.reference_force.data(), 3, "reference force");
    if (rot) check_finite(loads.reference_moment.data(), 3, "reference moment");
  }

  out.resize(1 + config.loads_payload_bytes());  // every byte is written below
  PayloadWriter w(out);
  w.u8(static_cast<std::uint8_t>(command));
  if (config.reference_node) {
    // The record is always sent, even with `use reference node forces, no` (spec §4.2).
    if (config.labels) {
      w.u32(loads.reference_label);
      w.u32(0);
    }
    w.doubles(loads.reference_force.data(), 3);
    if (rot) w.doubles(loads.reference_moment.data(), 3);
  }
  if (n > 0) {
    if (config.labels) {
      for (std::uint32_t l : loads.labels) w.u32(l);
      if (n % 2) w.u32(0);
    }
    w.doubles(loads.force.data(), 3 * n);
    if (rot) w.doubles(loads.moment.data(), 3 * n);
  }
  if (w.offset() != out.size()) throw std::logic_error("encode_loads: layout and size disagree");
}

}  // namespace dembridge::mbdyn
