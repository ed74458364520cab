// The configuration handshake (spec §3). Direction depends on who created the socket.
#pragma once

#include <array>
#include <cstdint>
#include <string>

#include "nodal_config.h"
#include "socket_transport.h"

namespace dembridge::mbdyn {

// The 9 request bytes 07 | flags | N, as the client sends them in one write.
std::array<std::uint8_t, 9> negotiation_request_bytes(const NodalConfig& config);

// MBDyn `create, yes` (we connected): send the request, expect 8. An answer 5 means MBDyn found
// a mismatch (it prints which one and exits): throws NegotiationError.
void negotiate_as_client(SocketTransport& transport, const NodalConfig& config, double timeout_s);

// MBDyn `create, no` (MBDyn connected to us): MBDyn sends 07 | flags | N and then 08 without
// waiting for an answer, so we read 10 bytes and send nothing on success. On a mismatch we send 5
// (MBDyn takes it as "peer requested end of simulation") and throw NegotiationError.
void accept_negotiation_as_server(SocketTransport& transport, const NodalConfig& config, double timeout_s);

// Compares what MBDyn announced with what we expect; returns "" when they agree, otherwise a
// sentence per difference, e.g. "wrong node count: MBDyn announces N=2, this peer expects 3".
std::string describe_mismatch(const NodalConfig& expected, std::uint32_t flags, std::uint32_t num_points);

}  // namespace dembridge::mbdyn
