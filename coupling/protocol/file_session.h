// The peer's side of MBDyn's file communicator for `external structural`, loose coupling
// (`"IN", unlink, "OUT", no clobber, ...` in MBDyn): MBDyn writes OUT (via a temporary file
// and a rename), the peer reads it and removes it, so that MBDyn, which waits with `no clobber`
// until OUT is gone, can write the next; the peer answers with IN, written to IN.tmp and renamed,
// so MBDyn never reads half a file, and only once MBDyn has removed the previous IN (`unlink`).
// There is no end-of-simulation message: MBDyn simply stops writing. Only MPI rank 0 owns one.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "nodal_config.h"
#include "nodal_message.h"
#include "peer_session.h"

namespace dembridge::mbdyn {

struct FileOptions {
  std::string in_path;   // MBDyn's input file: the loads we write
  std::string out_path;  // MBDyn's output file: the kinematics we read
  double sleep_s = 0.05;  // between two looks at a file
  int precision = 16;     // digits after the point of the loads we write (`%.<p>e`)
  double timeout_s = 300;  // per file waited for; < 0 waits forever
  NodalConfig nodal;
};

class FileSession {
 public:
  // Throws std::invalid_argument for a reference node or coupling other than loose (not
  // supported), and SystemError when IN already exists (a previous run's answer that MBDyn
  // would take for ours) or IN.tmp does; both are left untouched.
  explicit FileSession(const FileOptions& options);

  // Waits (timeout_s) for OUT, reads it, removes it and parses it. Throws TimeoutError naming the
  // file, MalformedMessageError as parse_kinematics_text.
  Received receive();
  const Kinematics& kinematics() const { return kinematics_; }
  // The kinematics in the socket's wire layout, for MPI ranks that decode them themselves.
  const std::vector<std::uint8_t>& raw_payload() const { return payload_; }
  // Waits (timeout_s) until MBDyn removed the previous IN, then writes IN.tmp and renames it to IN.
  // Labels are those of the last kinematics.
  void send_loads(const Loads& loads);

 private:
  FileOptions options_;
  Kinematics kinematics_;
  std::vector<std::uint8_t> payload_;
  std::uint64_t messages_ = 0;
};

}  // namespace dembridge::mbdyn
