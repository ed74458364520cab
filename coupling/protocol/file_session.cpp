#include "file_session.h"

#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <sys/stat.h>
#include <thread>
#include <unistd.h>

#include "deadline.h"
#include "file_text.h"
#include "protocol_error.h"

namespace dembridge::mbdyn {

namespace {

bool exists(const std::string& path) {
  struct stat st;
  return ::stat(path.c_str(), &st) == 0;
}

std::string os_error(const std::string& what) { return what + ": " + std::strerror(errno); }

// Sleeps in steps of sleep_s until ready() or the deadline; throws TimeoutError with why.
template <class Ready>
void wait_until(Ready ready, const FileOptions& o, const std::string& why) {
  const Deadline deadline(o.timeout_s);
  while (!ready()) {
    if (deadline.expired())
      throw TimeoutError(why + " (waited " + std::to_string(o.timeout_s) + " s, looking every " +
                         std::to_string(o.sleep_s) + " s)");
    std::this_thread::sleep_for(std::chrono::duration<double>(o.sleep_s));
  }
}

}  // namespace

FileSession::FileSession(const FileOptions& options) : options_(options) {
  if (options_.nodal.reference_node)
    throw std::invalid_argument("the file communicator is supported without reference node only");
  if (exists(options_.in_path))
    throw SystemError("MBDyn's input file " + options_.in_path +
                      " already exists (a previous run's loads?); MBDyn would read it as ours: remove it first");
  if (exists(options_.in_path + ".tmp"))
    throw SystemError(options_.in_path + ".tmp already exists: it is where the loads are written before the rename "
                      "to " + options_.in_path + "; remove it or choose another IN");
}

Received FileSession::receive() {
  const std::string& out = options_.out_path;
  wait_until([&] { return exists(out); }, options_, "MBDyn wrote no " + out);
  std::ifstream in(out, std::ios::binary);
  if (!in) throw SystemError(os_error("cannot open " + out));
  std::ostringstream text;
  text << in.rdbuf();
  in.close();
  // MBDyn's `no clobber` waits for this before it writes the next OUT
  if (::unlink(out.c_str()) != 0) throw SystemError(os_error("cannot remove " + out + " after reading it"));
  parse_kinematics_text(options_.nodal, text.str(), out, kinematics_);
  std::vector<WireSpan> spans;
  kinematics_wire_spans(options_.nodal, kinematics_, spans);  // same shape: the values stay
  payload_.clear();
  for (const WireSpan& s : spans) {
    const auto* p = static_cast<const std::uint8_t*>(s.data);
    if (p) payload_.insert(payload_.end(), p, p + s.size);
    else payload_.insert(payload_.end(), s.size, 0);
  }
  Received r;
  r.kind = Received::Kind::Kinematics;
  r.message_index = messages_;
  r.step = messages_;
  r.starts_new_step = true;
  ++messages_;
  return r;
}

void FileSession::send_loads(const Loads& loads) {
  const std::string& in = options_.in_path;
  wait_until([&] { return !exists(in); }, options_, "MBDyn did not read (unlink) its previous input file " + in);
  const std::string text = format_loads_text(options_.nodal, loads, kinematics_.labels, options_.precision);
  const std::string tmp = in + ".tmp";
  {
    std::ofstream f(tmp, std::ios::binary | std::ios::trunc);
    if (!f) throw SystemError(os_error("cannot write " + tmp));
    f << text;
    f.close();
    if (!f) throw SystemError(os_error("cannot write " + tmp));
  }
  if (std::rename(tmp.c_str(), in.c_str()) != 0) throw SystemError(os_error("cannot rename " + tmp + " to " + in));
}

}  // namespace dembridge::mbdyn
