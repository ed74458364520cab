// Flags and message lengths against the byte counts MBDyn accepted (spec §3, §4.2 table).
#include <gtest/gtest.h>

#include "negotiation.h"
#include "nodal_config.h"
#include "testpeer_wire.h"
#include "protocol_error.h"
#include "test_support.h"

using namespace dembridge::mbdyn;

namespace {

struct SpecCase {
  const char* name;
  NodalConfig config;
  std::uint32_t flags;  // 0 = not given by the spec
  std::size_t kinematics, loads;
};

NodalConfig make(std::uint32_t n, Rotation r, bool labels, bool acc, bool ref) {
  NodalConfig c;
  c.num_points = n;
  c.rotation = r;
  c.labels = labels;
  c.accelerations = acc;
  c.reference_node = ref;
  return c;
}

const SpecCase kSpecCases[] = {
    {"loose.mbd", make(2, Rotation::OrientationVector, false, false, false), 0x102, 192, 96},
    {"none", make(2, Rotation::None, false, false, false), 0x2, 96, 48},
    {"tight.mbd", make(2, Rotation::OrientationMatrix, true, true, false), 0x21a, 392, 104},
    {"refnode.mbd", make(3, Rotation::OrientationMatrix, true, false, true), 0x216, 600, 216},
};

}  // namespace

TEST(NodalLayout, FlagsAndSizesMatchVerifiedMbdynExamples) {
  for (const SpecCase& c : kSpecCases) {
    SCOPED_TRACE(c.name);
    EXPECT_EQ(c.config.flags(), c.flags);
    EXPECT_EQ(c.config.kinematics_payload_bytes(), c.kinematics);
    EXPECT_EQ(c.config.loads_payload_bytes(), c.loads);
  }
}

TEST(NodalLayout, TestPeerEncodesTheSameVerifiedSizes) {
  // The independent implementation must agree with the spec table too.
  for (const SpecCase& c : kSpecCases) {
    SCOPED_TRACE(c.name);
    const auto shape = test::to_peer(c.config);
    EXPECT_EQ(testpeer::negotiation_flags(shape), c.flags);
    std::vector<testpeer::NodeState> nodes(c.config.num_points);
    EXPECT_EQ(testpeer::encode_kinematics_payload(shape, testpeer::NodeState{}, nodes).size(), c.kinematics);
    EXPECT_EQ(testpeer::loads_payload_size(shape), c.loads);
  }
}

TEST(NodalLayout, NegotiationRequestBytesOfLooseExample) {
  // spec §3: loose.mbd -> 07 02 01 00 00 02 00 00 00
  const auto bytes = negotiation_request_bytes(kSpecCases[0].config);
  const std::array<std::uint8_t, 9> expected{0x07, 0x02, 0x01, 0x00, 0x00, 0x02, 0x00, 0x00, 0x00};
  EXPECT_EQ(bytes, expected);
}

TEST(NodalLayout, OddLabelCountIsPaddedToEightBytes) {
  // libmbc's bug (spec §7): N odd with labels must carry N+1 label words.
  const NodalConfig c = make(3, Rotation::None, true, false, false);
  EXPECT_EQ(c.label_block_bytes(), 16u);
  EXPECT_EQ(c.kinematics_payload_bytes(), 16u + 3 * 6 * 8);
  EXPECT_EQ(c.loads_payload_bytes(), 16u + 3 * 3 * 8);
}

TEST(NodalLayout, FromFlagsInvertsFlagsAndRejectsModal) {
  for (Rotation r : {Rotation::None, Rotation::OrientationVector, Rotation::OrientationMatrix, Rotation::Euler123})
    for (int bits = 0; bits < 8; ++bits) {
      const NodalConfig c = make(5, r, bits & 1, bits & 2, bits & 4);
      EXPECT_EQ(NodalConfig::from_flags(c.flags(), 5), c);
      // libmbc sets reference-rotation bits; external structural ignores them (spec §3).
      EXPECT_EQ(NodalConfig::from_flags(c.flags() | 0x2000, 5), c);
    }
  EXPECT_THROW(NodalConfig::from_flags(0x1, 2), NegotiationError);
  EXPECT_THROW(NodalConfig::from_flags(0x0, 2), NegotiationError);
  EXPECT_THROW(NodalConfig::from_flags(0x302, 2), NegotiationError);
}
