// MBDyn's modal FEM file: the recorded run's body.fem read back value by value, and malformed
// files refused with the file, the line and what was expected.
#include <gtest/gtest.h>

#include <string>

#include "modal_fem_file.h"

using namespace dembridge::mbdyn;

namespace {

const std::string kBody = std::string(DEMBRIDGE_MBDYN_EXT_DATA) + "/modal_body/body.fem";

// A small valid file (1 normal mode, 2 nodes) edited by the bad-input cases.
const std::string kSmall =
    "** RECORD GROUP 1, HEADER\n"
    "**   REVISION, NODE, NORMAL, ATTACHMENT, CONSTRAINT, REJECTED\n"
    "REV0 2 1 0 0 0\n"
    "** RECORD GROUP 2, FINITE ELEMENT NODE LIST\n"
    "a b\n"
    "** RECORD GROUP 5, NODAL X COORDINATES\n0.\n1.\n"
    "** RECORD GROUP 6, NODAL Y COORDINATES\n0.\n0.\n"
    "** RECORD GROUP 7, NODAL Z COORDINATES\n0.\n0.\n"
    "** RECORD GROUP 8, NON-ORTHOGONALIZED MODE SHAPES\n"
    "**    NORMAL MODE SHAPE #  1\n"
    "0. 0. 1. 0. 0. 0.\n"
    "0. 0. 2. 0. 0. 0.\n"
    "** END OF FILE\n";

std::string replaced(std::string s, const std::string& from, const std::string& to) {
  const auto at = s.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  return s.replace(at, from.size(), to);
}

void expect_error(const std::string& text, const std::string& part) {
  try {
    parse_fem_text(text, "bad.fem");
    ADD_FAILURE() << "accepted, expected an error containing: " << part;
  } catch (const FemFileError& e) {
    EXPECT_NE(std::string(e.what()).find(part), std::string::npos) << e.what();
    EXPECT_EQ(std::string(e.what()).rfind("FEM file 'bad.fem'", 0), 0u) << e.what();
  }
}

}  // namespace

TEST(ModalFemFile, RecordedBodyReadBack) {
  const FemModel m = read_fem_file(kBody);
  EXPECT_EQ(m.num_modes, 2u);
  ASSERT_EQ(m.num_nodes(), 3u);
  EXPECT_EQ(m.node_labels, (std::vector<std::string>{"1", "2", "3"}));
  EXPECT_EQ(m.node_xyz[1], (std::array<double, 3>{0.5, 0.0, 0.0}));
  EXPECT_EQ(m.node_xyz[2], (std::array<double, 3>{1.0, 0.0, 0.0}));
  // mode 1 along z, mode 2 along y, nodal shape (1, -2, 1)
  EXPECT_EQ(m.translation(0, 1), (std::array<double, 3>{0.0, 0.0, -2.0}));
  EXPECT_EQ(m.translation(1, 2), (std::array<double, 3>{0.0, 1.0, 0.0}));
  EXPECT_EQ(m.mass, (std::vector<double>{6.0, 0.0, 0.0, 6.0}));
  EXPECT_EQ(m.stiffness, (std::vector<double>{600.0, 0.0, 0.0, 1350.0}));
  EXPECT_EQ(m.damping, (std::vector<double>{1.2, 0.0, 0.0, 1.8}));
  EXPECT_EQ(m.node_index("3"), 2u);
  EXPECT_THROW(m.node_index("4"), FemFileError);
}

TEST(ModalFemFile, RejectedModesComeFirstAndAreDropped) {
  std::string t = replaced(kSmall, "REV0 2 1 0 0 0", "REV0 2 2 0 0 1");
  t = replaced(t, "**    NORMAL MODE SHAPE #  1\n", "** rejected\n9. 9. 9. 9. 9. 9.\n9. 9. 9. 9. 9. 9.\n** kept\n");
  const FemModel m = parse_fem_text(t, "x.fem");
  EXPECT_EQ(m.num_modes, 1u);
  EXPECT_EQ(m.translation(0, 1), (std::array<double, 3>{0.0, 0.0, 2.0}));
}

TEST(ModalFemFile, BadFilesNameFileLineAndExpectation) {
  EXPECT_EQ(parse_fem_text(kSmall, "ok.fem").num_modes, 1u);
  expect_error(replaced(kSmall, "0. 0. 2. 0. 0. 0.\n", ""), "line 15: RECORD GROUP 8 has 6 values, expected 12");
  expect_error(replaced(kSmall, "0. 0. 2. 0. 0. 0.", "0. 0. two 0. 0. 0."), "line 18: expected a number, got 'two'");
  expect_error(replaced(kSmall, "a b\n", "a\n"), "RECORD GROUP 2 has 1 values, expected 2");
  expect_error(replaced(kSmall, "** RECORD GROUP 6, NODAL Y COORDINATES\n0.\n0.\n", ""), "RECORD GROUP 6 missing");
  expect_error(replaced(kSmall, "** RECORD GROUP 7", "** RECORD GROUP 5"), "RECORD GROUP 5 given twice");
  expect_error(replaced(kSmall, "REV0 2 1 0 0 0", "REV0 2 x 0 0 0"), "expected a non-negative integer for NORMAL");
  expect_error(replaced(kSmall, "REV0 2 1 0 0 0", "REV0 2 1 0 0 1"), "expected fewer rejected modes than modes");
  expect_error("1 2 3\n" + kSmall, "line 1: expected '** RECORD GROUP 1' before any value");
  expect_error(replaced(kSmall, "** RECORD GROUP 8", "** RECORD GROUP 14"), "expected record groups 1 to 13");
  EXPECT_THROW(read_fem_file("/nonexistent/body.fem"), FemFileError);
}
