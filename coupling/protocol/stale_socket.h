// Clearing the way for a Unix socket we are about to create (`fix mbdyn ... create no`): only a
// socket file that nobody listens on (left by a crashed run) may be removed; anything else at the
// path is the user's and is left untouched.
#pragma once

#include <string>

namespace dembridge::mbdyn {

// Nothing at path: returns. A socket nobody listens on: unlinks it. Throws SystemError, naming
// path and what is there, for a socket somebody listens on or for anything that is not a socket
// (regular file, folder, link).
void remove_stale_unix_socket(const std::string& path);

}  // namespace dembridge::mbdyn
