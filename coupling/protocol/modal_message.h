// The payloads and negotiation of MBDyn's `external modal` force (socket communicator):
// kinematics of the modal node and the modal coordinates MBDyn -> peer, the node's force and
// moment and one generalized force per mode peer -> MBDyn. Verified against recorded runs of
// MBDyn 1.7.3 (tests/data/mbdyn-ext/modal_body).
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "nodal_message.h"
#include "wire_format.h"

namespace dembridge::mbdyn {

// `type, rigid | modal | all` of the element: which parts cross the socket.
enum class ModalType { All, Rigid, Modal };

// Parses "all", "rigid" or "modal"; throws std::invalid_argument naming the word otherwise.
ModalType modal_type_from_name(const std::string& name);
std::string modal_type_name(ModalType type);

struct ModalConfig {
  ModalType type = ModalType::All;
  std::uint32_t num_modes = 0;  // modes of the modal joint; announced also with type rigid

  bool has_rigid() const { return type != ModalType::Modal; }
  bool has_modes() const { return type != ModalType::Rigid; }
  // MBC_MODAL, plus the reference-node bit when the rigid part is exchanged.
  std::uint32_t flags() const;
  // x 3, R 9, v 3, omega 3 (rigid) then q M, qdot M (modal).
  std::size_t kinematics_doubles() const;
  std::size_t kinematics_payload_bytes() const { return 8 * kinematics_doubles(); }
  // F 3, M 3 (rigid) then p M (modal).
  std::size_t loads_doubles() const;
  std::size_t loads_payload_bytes() const { return 8 * loads_doubles(); }
  std::string describe() const;
};

// One kinematics message. Absent parts stay at their defaults (x = v = omega = 0, R = I,
// q and qdot empty).
struct ModalKinematics {
  Command command = Command::RegularDataAndGotoNextStep;
  Vec3 x{};
  Matrix3 R{1, 0, 0, 0, 1, 0, 0, 0, 1};  // row-major; column-major on the wire
  Vec3 v{}, omega{};
  std::vector<double> q, qdot;
};

// One answer: global force and moment about the modal node, and the generalized forces.
struct ModalLoads {
  Vec3 force{}, moment{};
  std::vector<double> p;
};

// Decodes a kinematics payload (the bytes after the command byte). Throws MalformedMessageError
// if the size is not config.kinematics_payload_bytes() or a value is not finite (naming it).
ModalKinematics decode_modal_kinematics(const ModalConfig& config, Command command,
                                        const std::uint8_t* payload, std::size_t size);

// Builds the answer, command byte then payload, for one write. command must be 2 or 6; throws
// std::invalid_argument if p has not num_modes values (type modal/all) and MalformedMessageError
// on a non-finite load.
std::vector<std::uint8_t> encode_modal_loads(const ModalConfig& config, Command command,
                                             const ModalLoads& loads);

// The 9 request bytes 07 | flags | N.
std::vector<std::uint8_t> modal_negotiation_request_bytes(const ModalConfig& config);

// What MBDyn would object to in an announced flags/N against config ("" when they agree). MBDyn
// checks the modal/nodal kind, the reference-node bit and N only.
std::string describe_modal_mismatch(const ModalConfig& expected, std::uint32_t flags,
                                    std::uint32_t num_modes);

}  // namespace dembridge::mbdyn
