#include "wire_format.h"

namespace dembridge::mbdyn {

int rotation_doubles(Rotation r) {
  switch (r) {
    case Rotation::None: return 0;
    case Rotation::OrientationVector: return 3;
    case Rotation::OrientationMatrix: return 9;
    case Rotation::Euler123: return 3;
  }
  return 0;
}

std::string rotation_name(Rotation r) {
  switch (r) {
    case Rotation::None: return "none";
    case Rotation::OrientationVector: return "orientation vector";
    case Rotation::OrientationMatrix: return "orientation matrix";
    case Rotation::Euler123: return "euler 123";
  }
  return "unknown rotation";
}

bool is_known_command(std::uint8_t byte) {
  return byte == 2 || (byte >= 4 && byte <= 8);
}

std::string command_name(std::uint8_t byte) {
  const char* name = "unknown";
  switch (byte) {
    case 2: name = "regular data"; break;
    case 4: name = "goto next step"; break;
    case 5: name = "abort"; break;
    case 6: name = "regular data and goto next step"; break;
    case 7: name = "negotiation"; break;
    case 8: name = "ok"; break;
    default: break;
  }
  return std::to_string(static_cast<unsigned>(byte)) + " (" + name + ")";
}

}  // namespace dembridge::mbdyn
