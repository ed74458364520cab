#include "stale_socket.h"

#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/un.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

#include "protocol_error.h"
#include "socket_address.h"

namespace dembridge::mbdyn {

namespace {

const char* kind_of(mode_t m) {
  if (S_ISREG(m)) return "a regular file";
  if (S_ISDIR(m)) return "a folder";
  if (S_ISLNK(m)) return "a symbolic link";
  if (S_ISFIFO(m)) return "a FIFO";
  return "not a socket";
}

// A blocking connect to a Unix socket answers at once: refused when nobody listens.
bool somebody_listens(const std::string& path) {
  const sockaddr_un addr = unix_address(path);
  const int fd = ::socket(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0);
  if (fd < 0) return false;
  const bool listening = ::connect(fd, reinterpret_cast<const sockaddr*>(&addr), sizeof addr) == 0 || errno == EAGAIN;
  ::close(fd);
  return listening;
}

}  // namespace

void remove_stale_unix_socket(const std::string& path) {
  struct stat st {};
  if (::lstat(path.c_str(), &st) != 0) {
    if (errno == ENOENT) return;
    throw SystemError("cannot inspect '" + path + "': " + std::strerror(errno));
  }
  if (!S_ISSOCK(st.st_mode))
    throw SystemError("'" + path + "' exists and is " + kind_of(st.st_mode) +
                      ", not a socket: it is left untouched; remove it or choose another socket path");
  if (somebody_listens(path))
    throw SystemError("another process is listening on the socket '" + path + "'");
  if (::unlink(path.c_str()) != 0 && errno != ENOENT)
    throw SystemError("cannot remove the stale socket '" + path + "': " + std::strerror(errno));
}

}  // namespace dembridge::mbdyn
