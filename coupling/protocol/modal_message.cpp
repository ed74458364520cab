#include "modal_message.h"

#include <cmath>
#include <cstring>
#include <sstream>
#include <stdexcept>

#include "protocol_error.h"

namespace dembridge::mbdyn {

ModalType modal_type_from_name(const std::string& name) {
  if (name == "all") return ModalType::All;
  if (name == "rigid") return ModalType::Rigid;
  if (name == "modal") return ModalType::Modal;
  throw std::invalid_argument("expected all, rigid or modal after type, got '" + name + "'");
}

std::string modal_type_name(ModalType type) {
  switch (type) {
    case ModalType::All: return "all";
    case ModalType::Rigid: return "rigid";
    case ModalType::Modal: return "modal";
  }
  return "?";
}

std::uint32_t ModalConfig::flags() const {
  return flag::Modal | (has_rigid() ? flag::ReferenceNode : 0u);
}

std::size_t ModalConfig::kinematics_doubles() const {
  return (has_rigid() ? 18 : 0) + (has_modes() ? 2 * std::size_t{num_modes} : 0);
}

std::size_t ModalConfig::loads_doubles() const {
  return (has_rigid() ? 6 : 0) + (has_modes() ? std::size_t{num_modes} : 0);
}

std::string ModalConfig::describe() const {
  return "external modal, type " + modal_type_name(type) + ", " + std::to_string(num_modes) + " modes";
}

namespace {

// Reads n doubles from the payload at *off into out, naming the field of a non-finite one.
void take(const std::uint8_t* payload, std::size_t& off, double* out, std::size_t n, const char* field) {
  std::memcpy(out, payload + off, 8 * n);
  off += 8 * n;
  for (std::size_t i = 0; i < n; ++i)
    if (!std::isfinite(out[i])) {
      std::ostringstream msg;
      msg << "MBDyn external modal kinematics: expected finite values, received " << out[i]
          << " in field '" << field << "', component " << i;
      throw MalformedMessageError(msg.str());
    }
}

void put(std::vector<std::uint8_t>& out, const double* v, std::size_t n, const char* field) {
  for (std::size_t i = 0; i < n; ++i)
    if (!std::isfinite(v[i])) {
      std::ostringstream msg;
      msg << "external modal loads: expected finite values, got " << v[i] << " in '" << field
          << "', component " << i;
      throw MalformedMessageError(msg.str());
    }
  const std::size_t at = out.size();
  out.resize(at + 8 * n);
  std::memcpy(out.data() + at, v, 8 * n);
}

}  // namespace

ModalKinematics decode_modal_kinematics(const ModalConfig& config, Command command,
                                        const std::uint8_t* payload, std::size_t size) {
  if (size != config.kinematics_payload_bytes())
    throw MalformedMessageError("MBDyn external modal kinematics: expected " +
                                std::to_string(config.kinematics_payload_bytes()) + " bytes (" +
                                config.describe() + "), received " + std::to_string(size));
  ModalKinematics k;
  k.command = command;
  std::size_t off = 0;
  if (config.has_rigid()) {
    double wire_r[9];
    take(payload, off, k.x.data(), 3, "x");
    take(payload, off, wire_r, 9, "R");
    k.R = matrix_from_wire_column_major(wire_r);
    take(payload, off, k.v.data(), 3, "v");
    take(payload, off, k.omega.data(), 3, "omega");
  }
  if (config.has_modes()) {
    k.q.resize(config.num_modes);
    k.qdot.resize(config.num_modes);
    take(payload, off, k.q.data(), config.num_modes, "q");
    take(payload, off, k.qdot.data(), config.num_modes, "qdot");
  }
  return k;
}

std::vector<std::uint8_t> encode_modal_loads(const ModalConfig& config, Command command,
                                             const ModalLoads& loads) {
  if (command != Command::RegularData && command != Command::RegularDataAndGotoNextStep)
    throw std::invalid_argument("external modal loads: command must be 2 or 6, got " +
                                command_name(static_cast<std::uint8_t>(command)));
  if (config.has_modes() && loads.p.size() != config.num_modes)
    throw std::invalid_argument("external modal loads: expected " + std::to_string(config.num_modes) +
                                " generalized forces, got " + std::to_string(loads.p.size()));
  std::vector<std::uint8_t> out{static_cast<std::uint8_t>(command)};
  out.reserve(1 + config.loads_payload_bytes());
  if (config.has_rigid()) {
    put(out, loads.force.data(), 3, "F");
    put(out, loads.moment.data(), 3, "M");
  }
  if (config.has_modes()) put(out, loads.p.data(), config.num_modes, "p");
  return out;
}

std::vector<std::uint8_t> modal_negotiation_request_bytes(const ModalConfig& config) {
  std::vector<std::uint8_t> bytes(9);
  bytes[0] = static_cast<std::uint8_t>(Command::Negotiation);
  const std::uint32_t flags = config.flags(), n = config.num_modes;
  std::memcpy(&bytes[1], &flags, 4);
  std::memcpy(&bytes[5], &n, 4);
  return bytes;
}

std::string describe_modal_mismatch(const ModalConfig& expected, std::uint32_t flags,
                                    std::uint32_t num_modes) {
  std::ostringstream why;
  if (!(flags & flag::Modal) || (flags & flag::Nodal))
    why << "MBDyn announces a nodal element (flags 0x" << std::hex << flags << std::dec
        << "), this peer expects external modal; ";
  const bool rigid = (flags & flag::ReferenceNode) != 0;
  if (rigid != expected.has_rigid())
    why << "rigid part mismatch: MBDyn " << (rigid ? "exchanges" : "does not exchange")
        << " the modal node's motion, this peer expects type " << modal_type_name(expected.type) << "; ";
  if (num_modes != expected.num_modes)
    why << "wrong mode count: MBDyn announces N=" << num_modes << ", this peer expects "
        << expected.num_modes << "; ";
  return why.str();
}

}  // namespace dembridge::mbdyn
