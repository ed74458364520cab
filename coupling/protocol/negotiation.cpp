#include "negotiation.h"

#include <cstring>
#include <sstream>

#include "protocol_error.h"

namespace dembridge::mbdyn {

namespace {

std::string hex(std::uint32_t v) {
  std::ostringstream s;
  s << "0x" << std::hex << v;
  return s.str();
}

std::string yes_no(bool b) { return b ? "yes" : "no"; }

}  // namespace

std::array<std::uint8_t, 9> negotiation_request_bytes(const NodalConfig& config) {
  std::array<std::uint8_t, 9> bytes{};
  bytes[0] = static_cast<std::uint8_t>(Command::Negotiation);
  const std::uint32_t flags = config.flags();
  const std::uint32_t n = config.num_points;
  std::memcpy(&bytes[1], &flags, 4);
  std::memcpy(&bytes[5], &n, 4);
  return bytes;
}

void negotiate_as_client(SocketTransport& transport, const NodalConfig& config, double timeout_s) {
  const auto request = negotiation_request_bytes(config);
  transport.write_all(request.data(), request.size(), timeout_s, "the negotiation request");
  std::uint8_t answer = 0;
  try {
    transport.read_exact(&answer, 1, timeout_s, "the negotiation answer (8 = ok)");
  } catch (const PeerClosedError& e) {
    throw PeerClosedError(std::string(e.what()) +
                          "; MBDyn probably rejected the configuration (" + config.describe() + ")");
  }
  if (answer == static_cast<std::uint8_t>(Command::Ok)) return;
  if (answer == static_cast<std::uint8_t>(Command::Abort))
    throw NegotiationError("MBDyn refused the negotiation: expected answer 8 (ok), received 5 for flags " +
                           hex(config.flags()) + " (" + config.describe() +
                           "); MBDyn's log names the mismatch; check the node count, `orientation` "
                           "(default orientation matrix), `labels`, `accelerations` and `reference node` "
                           "of the external structural element");
  throw MalformedMessageError("negotiation: expected answer 8 (ok) or 5 (refused) from MBDyn, received " +
                              command_name(answer));
}

std::string describe_mismatch(const NodalConfig& expected, std::uint32_t flags, std::uint32_t num_points) {
  std::ostringstream why;
  if (num_points != expected.num_points)
    why << "wrong node count: MBDyn announces N=" << num_points << ", this peer expects "
        << expected.num_points << "; ";
  NodalConfig announced;
  try {
    announced = NodalConfig::from_flags(flags, num_points);
  } catch (const NegotiationError& e) {
    why << e.what() << "; ";
    return why.str();
  }
  if (announced.rotation != expected.rotation)
    why << "orientation mismatch: MBDyn announces " << rotation_name(announced.rotation)
        << ", this peer expects " << rotation_name(expected.rotation) << "; ";
  if (announced.labels != expected.labels)
    why << "labels mismatch: MBDyn " << yes_no(announced.labels) << ", this peer "
        << yes_no(expected.labels) << "; ";
  if (announced.accelerations != expected.accelerations)
    why << "accelerations mismatch: MBDyn " << yes_no(announced.accelerations) << ", this peer "
        << yes_no(expected.accelerations) << "; ";
  if (announced.reference_node != expected.reference_node)
    why << "reference node mismatch: MBDyn " << yes_no(announced.reference_node) << ", this peer "
        << yes_no(expected.reference_node) << "; ";
  return why.str();
}

void accept_negotiation_as_server(SocketTransport& transport, const NodalConfig& config, double timeout_s) {
  std::uint8_t bytes[10];
  transport.read_exact(bytes, sizeof bytes, timeout_s,
                       "the negotiation request (07 | flags | N | 08)");
  auto fail = [&](const std::string& message) {
    transport.try_write_byte(static_cast<std::uint8_t>(Command::Abort), 1.0);
    throw NegotiationError(message);
  };
  if (bytes[0] != static_cast<std::uint8_t>(Command::Negotiation))
    fail("negotiation: expected command 7 (negotiation) from MBDyn, received " + command_name(bytes[0]));
  std::uint32_t flags, n;
  std::memcpy(&flags, &bytes[1], 4);
  std::memcpy(&n, &bytes[5], 4);
  if (bytes[9] != static_cast<std::uint8_t>(Command::Ok))
    fail("negotiation: expected MBDyn's unsolicited 8 (ok) after flags and N, received " +
         command_name(bytes[9]));
  const std::string mismatch = describe_mismatch(config, flags, n);
  if (!mismatch.empty())
    fail("negotiation with MBDyn failed (flags " + hex(flags) + ", N=" + std::to_string(n) +
         "; expected flags " + hex(config.flags()) + ", N=" + std::to_string(config.num_points) +
         "): " + mismatch);
}

}  // namespace dembridge::mbdyn
