// Exceptions of the peer-side protocol library. Every message names what was expected and what
// was received, so a LAMMPS error line is enough to diagnose a broken coupling.
#pragma once

#include <stdexcept>
#include <string>

namespace dembridge::mbdyn {

// Base of every failure of the protocol library.
class ProtocolError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// A blocking call (connect, accept, read, write) did not finish before its deadline (spec P4).
class TimeoutError : public ProtocolError {
 public:
  using ProtocolError::ProtocolError;
};

// MBDyn closed the connection (EOF, ECONNRESET, EPIPE) where more data was expected.
class PeerClosedError : public ProtocolError {
 public:
  using ProtocolError::ProtocolError;
};

// The two sides disagree on the configuration (answer 5, or mismatching flags / node count).
class NegotiationError : public ProtocolError {
 public:
  using ProtocolError::ProtocolError;
};

// Bytes that do not form a valid message: unknown command, wrong length, non-finite values.
class MalformedMessageError : public ProtocolError {
 public:
  using ProtocolError::ProtocolError;
};

// An operating-system call failed for another reason (socket, bind, ...).
class SystemError : public ProtocolError {
 public:
  using ProtocolError::ProtocolError;
};

}  // namespace dembridge::mbdyn
