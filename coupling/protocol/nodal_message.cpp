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

// labels: the points' labels, or nullptr without labels.
void require_finite(const double* values, std::size_t per_point, std::size_t points,
                    const char* field, const std::uint32_t* labels) {
  if (all_finite(values, per_point * points)) return;
  for (std::size_t i = 0; i < points; ++i)
    for (std::size_t k = 0; k < per_point; ++k) {
      const double value = values[i * per_point + k];
      if (std::isfinite(value)) continue;
      std::ostringstream msg;
      msg << "MBDyn kinematics: expected finite values, received " << value << " in field '"
          << field << "' of point " << i;
      if (labels) msg << " (label " << labels[i] << ")";
      msg << ", component " << k;
      throw MalformedMessageError(msg.str());
    }
}

// Appends n bytes at p to a layout (p is written when a message is read into the layout).
void append_span(std::vector<WireSpan>& out, const void* p, std::size_t n) {
  if (n) out.push_back({const_cast<void*>(p), n});
}
void append_pad(std::vector<WireSpan>& out, std::size_t n) { out.push_back({nullptr, n}); }

// The kinematics layout over k as it is (already shaped for config): the wire order of spec §4.1.
void kinematics_spans(const NodalConfig& config, const Kinematics& k, std::vector<WireSpan>& out) {
  const bool acc = config.accelerations;
  out.clear();
  if (config.reference_node) {
    const ReferenceKinematics& ref = k.reference;
    const bool rrot = config.record_has_omega();
    if (config.labels) {
      append_span(out, &ref.label, 4);
      if (!config.mapping_reference) append_pad(out, 4);  // ignored on receipt (spec §2)
    }
    append_span(out, ref.x.data(), 24);
    append_span(out, ref.orientation.data(), 8 * static_cast<std::size_t>(rotation_doubles(config.record_rotation())));
    append_span(out, ref.v.data(), 24);
    if (rrot) append_span(out, ref.omega.data(), 24);
    if (acc) append_span(out, ref.a.data(), 24);
    if (acc && rrot) append_span(out, ref.omega_dot.data(), 24);
  }
  if (config.num_points > 0) {
    if (config.labels) {
      append_span(out, k.labels.data(), 4 * k.labels.size());
      if (config.num_points % 2) append_pad(out, 4);
    }
    // absent blocks are empty vectors: no span
    for (const std::vector<double>* v : {&k.x, &k.orientation, &k.v, &k.omega, &k.a, &k.omega_dot})
      append_span(out, v->data(), 8 * v->size());
  }
}

// Copies the pieces into out (size bytes), back to back (pads zero); returns the bytes written.
std::size_t gather(const std::vector<WireSpan>& spans, std::uint8_t* out, std::size_t size) {
  std::size_t off = 0;
  for (const WireSpan& s : spans) {
    if (s.size > size - off) throw std::logic_error("gather: the layout exceeds the message size");
    if (s.data)
      std::memcpy(out + off, s.data, s.size);
    else
      std::memset(out + off, 0, s.size);
    off += s.size;
  }
  return off;
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
  return matrix_from_wire(reference_rotation, reference.orientation.data());
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

void kinematics_wire_spans(const NodalConfig& config, Kinematics& k, std::vector<WireSpan>& out) {
  const std::size_t n = config.num_points;
  const std::size_t nr = config.rotation_doubles();
  const bool rot = config.has_rotation();
  const bool acc = config.accelerations;
  // k's vectors keep their capacity from message to message (no allocation, no zero fill); the
  // fields this layout lacks are emptied, as in a fresh Kinematics.
  k.rotation = config.rotation;
  k.reference_rotation = config.record_rotation();
  k.has_reference = config.reference_node;
  k.reference = ReferenceKinematics{};
  k.labels.resize(config.labels ? n : 0);
  k.x.resize(3 * n);
  k.orientation.resize(rot ? nr * n : 0);
  k.v.resize(3 * n);
  k.omega.resize(rot ? 3 * n : 0);
  k.a.resize(acc ? 3 * n : 0);
  k.omega_dot.resize(acc && rot ? 3 * n : 0);
  kinematics_spans(config, k, out);
}

void validate_kinematics(const NodalConfig& config, const Kinematics& k) {
  const std::size_t n = config.num_points;
  const std::size_t nr = config.rotation_doubles();
  const bool rot = config.has_rotation();
  const bool acc = config.accelerations;
  if (config.reference_node) {
    const ReferenceKinematics& ref = k.reference;
    const std::uint32_t* lab = config.labels ? &ref.label : nullptr;
    require_finite(ref.x.data(), 3, 1, "reference x", lab);
    require_finite(ref.orientation.data(), rotation_doubles(config.record_rotation()), 1, "reference orientation", lab);
    require_finite(ref.v.data(), 3, 1, "reference v", lab);
    require_finite(ref.omega.data(), 3, 1, "reference omega", lab);
    require_finite(ref.a.data(), 3, 1, "reference a", lab);
    require_finite(ref.omega_dot.data(), 3, 1, "reference omega_dot", lab);
  }
  if (n > 0) {
    const std::uint32_t* lab = config.labels ? k.labels.data() : nullptr;
    require_finite(k.x.data(), 3, n, "x", lab);
    require_finite(k.orientation.data(), nr, rot ? n : 0, "orientation", lab);
    require_finite(k.v.data(), 3, n, "v", lab);
    require_finite(k.omega.data(), 3, rot ? n : 0, "omega", lab);
    require_finite(k.a.data(), 3, acc ? n : 0, "a", lab);
    require_finite(k.omega_dot.data(), 3, (acc && rot) ? n : 0, "omega_dot", lab);
  }
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
  k.command = command;
  thread_local std::vector<WireSpan> spans;  // kept: no allocation per message
  kinematics_wire_spans(config, k, spans);
  std::size_t off = 0;
  for (const WireSpan& s : spans) {
    // the size was checked above; this guards the layout itself
    if (s.size > size - off) throw std::logic_error("decode_kinematics: read past the checked size");
    if (s.data) std::memcpy(s.data, payload + off, s.size);
    off += s.size;
  }
  if (off != size) throw std::logic_error("decode_kinematics: layout and size disagree");
  validate_kinematics(config, k);
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

namespace {
// encode_loads' checks: a command that carries loads, sizes matching config, finite values.
void check_loads(const NodalConfig& config, Command command, const Loads& loads,
                 const std::vector<std::uint32_t>& labels) {
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
  if (config.labels && labels.size() != n) size_error("labels", labels.size(), n);
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
    if (config.record_has_omega()) check_finite(loads.reference_moment.data(), 3, "reference moment");
  }
}

// The whole loads message (command byte, then payload) as pieces: *command_byte must hold the
// command while the pieces are used.
void loads_wire_spans(const NodalConfig& config, const std::uint8_t* command_byte, const Loads& loads,
                      const std::vector<std::uint32_t>& labels, const std::uint32_t* reference_label,
                      std::vector<WireSpan>& out) {
  const std::size_t n = config.num_points;
  const bool rot = config.has_rotation();
  out.clear();
  append_span(out, command_byte, 1);
  if (config.reference_node) {
    // The record is always sent, even with `use reference node forces, no` (spec §4.2).
    if (config.labels) {
      append_span(out, reference_label, 4);
      if (!config.mapping_reference) append_pad(out, 4);
    }
    append_span(out, loads.reference_force.data(), 24);
    if (config.record_has_omega()) append_span(out, loads.reference_moment.data(), 24);
  }
  if (n > 0) {
    if (config.labels) {
      append_span(out, labels.data(), 4 * n);
      if (n % 2) append_pad(out, 4);
    }
    append_span(out, loads.force.data(), 24 * n);
    if (rot) append_span(out, loads.moment.data(), 24 * n);
  }
}

}  // namespace

void encode_loads_into(const NodalConfig& config, Command command, const Loads& loads,
                       std::vector<std::uint8_t>& out) {
  encode_loads_into(config, command, loads, loads.labels, &loads.reference_label, out);
}

void encode_loads_into(const NodalConfig& config, Command command, const Loads& loads,
                       const std::vector<std::uint32_t>& labels, const std::uint32_t* reference_label,
                       std::vector<std::uint8_t>& out) {
  check_loads(config, command, loads, labels);
  const std::uint8_t cmd = static_cast<std::uint8_t>(command);
  thread_local std::vector<WireSpan> spans;  // kept: no allocation per message
  loads_wire_spans(config, &cmd, loads, labels, reference_label, spans);
  out.resize(1 + config.loads_payload_bytes());  // every byte is written below
  if (gather(spans, out.data(), out.size()) != out.size()) throw std::logic_error("encode_loads: layout and size disagree");
}

}  // namespace dembridge::mbdyn
