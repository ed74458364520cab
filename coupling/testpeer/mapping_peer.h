// The test peer as MBDyn's `external structural mapping` element on a cantilever of beam2
// elements (cantilever_model.h): every node carries the same offset points, the points are mapped
// to M points by a sparse matrix H (MBDyn's `sparse mapping file`: `row col value` triplets,
// 1-based, `#` comment lines, a repeated entry overwrites), no reference node, no labels, no
// accelerations. Wire (as recorded from MBDyn 1.7.3): 07|0x2|M from the peer, 08; kinematics
// q = H x, q' = H x' (x = x_n + R_n o, x' = v_n + w_n x R_n o), 6M doubles; loads p, 3M doubles,
// applied as f = H^T p at the points, each node getting the sum of its points' f and the sum of
// (R_n o) x f with R_n as it is when the loads arrive, fixed until the next loads.
// Sequence: loose: 6|t0, read by the initial derivatives; per step 6|prediction; tight: 2|t0,
// then per step 2|prediction and 2|iterate after every Newton update until the peer answers 6;
// 5 after the last step.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "cantilever_model.h"
#include "testpeer_socket.h"

namespace dembridge::mbdyn::testpeer {

struct SparseEntry {
  int row = 0, col = 0;  // 0-based
  double value = 0;
};

// Reads MBDyn's sparse mapping file; throws std::runtime_error naming the line on bad input.
std::vector<SparseEntry> read_sparse_mapping(const std::string& path, int rows, int cols);

struct MappingPeerSetup {
  SocketPlace place;
  CantileverSpec model;
  std::vector<V3> offsets;  // on every node, in this order
  int mapped_points = 0;
  std::vector<SparseEntry> mapping;
  double tolerance = 1e-9;
  int max_iterations = 20;
  int derivatives_max_iterations = 10;
  bool tight = false;
  int steps = 10;
  double dt = 1e-3;
  double accept_timeout_s = 30, io_timeout_s = 30;
  std::string trajectory;  // if set: t, then per node x R(row by row) v w
  std::function<void()> on_listening;
};

struct MappingPeerOutcome {
  int exit_status = 1;  // MBDyn's: 0 completed, 1 error, 2 interrupted
  std::string log;
  int kinematics_sent = 0;
};

MappingPeerOutcome run_mapping_test_peer(const MappingPeerSetup& setup);

}  // namespace dembridge::mbdyn::testpeer
