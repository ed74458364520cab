// external modal: the message layouts against real MBDyn 1.7.3 transcripts (modal_body, recorded
// by a scripted peer whose law is written in tests/data/mbdyn-ext/README.md). Every recorded
// kinematics message is decoded, the peer's law is evaluated here from its formulas, and the
// encoded answer must equal the recorded answer byte for byte.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "modal_message.h"
#include "protocol_error.h"

using namespace dembridge::mbdyn;

namespace {

const std::string kDir = std::string(DEMBRIDGE_MBDYN_EXT_DATA) + "/modal_body/";

struct Row {
  bool from_mbdyn;
  int cmd;
  std::vector<double> values;
};

std::vector<Row> read_transcript(const std::string& name) {
  std::ifstream in(kDir + name);
  EXPECT_TRUE(in.good()) << kDir + name;
  std::vector<Row> rows;
  std::string line;
  std::getline(in, line);  // header
  while (std::getline(in, line)) {
    std::istringstream s(line);
    std::string seq, dir, cmd, values;
    std::getline(s, seq, ',');
    std::getline(s, dir, ',');
    std::getline(s, cmd, ',');
    std::getline(s, values);
    Row r{dir == "mbdyn->peer", std::stoi(cmd), {}};
    std::istringstream v(values);
    for (std::string word; v >> word;) r.values.push_back(std::strtod(word.c_str(), nullptr));
    rows.push_back(r);
  }
  return rows;
}

std::vector<std::uint8_t> bytes_of(const std::vector<double>& v) {
  std::vector<std::uint8_t> b(8 * v.size());
  std::memcpy(b.data(), v.data(), b.size());
  return b;
}

// The recording peer's law for modal (README: kr 40, cr 0.8, kt 30, kq (300, 600), cq (1, 2),
// rest x0 = 0, R0 = I, q0 = 0; theta the rotation vector of R).
ModalLoads peer_law(const ModalConfig& c, const ModalKinematics& k) {
  ModalLoads l;
  if (c.has_rigid()) {
    const auto& R = k.R;  // row-major
    const double cosine = std::max(-1.0, std::min(1.0, 0.5 * (R[0] + R[4] + R[8] - 1.0)));
    const double angle = std::acos(cosine);
    const double f = angle < 1e-8 ? 0.5 * (1.0 + angle * angle / 6.0) : angle / (2.0 * std::sin(angle));
    const double axis[3] = {R[7] - R[5], R[2] - R[6], R[3] - R[1]};
    for (int a = 0; a < 3; ++a) {
      l.force[a] = -40.0 * (k.x[a] - 0.0) - 0.8 * k.v[a];
      l.moment[a] = -30.0 * (f * axis[a]);
    }
  }
  if (c.has_modes()) {
    const double kq[2] = {300.0, 600.0}, cq[2] = {1.0, 2.0};
    for (std::size_t m = 0; m < c.num_modes; ++m) l.p.push_back(-kq[m] * k.q[m] - cq[m] * k.qdot[m]);
  }
  return l;
}

// Replays a transcript: returns the number of answers that differ from the recorded ones;
// permute (applied to each kinematics message's doubles first) models a wrong field order.
int replay(const ModalConfig& c, const std::vector<Row>& rows, int& answers,
           void (*permute)(std::vector<double>&) = nullptr) {
  int mismatches = 0;
  answers = 0;
  for (std::size_t i = 0; i + 1 < rows.size(); ++i) {
    if (!rows[i].from_mbdyn || (rows[i].cmd != 2 && rows[i].cmd != 6)) continue;
    const Row& answer = rows[i + 1];
    EXPECT_FALSE(answer.from_mbdyn);
    std::vector<double> wire = rows[i].values;
    if (permute) permute(wire);
    const auto payload = bytes_of(wire);
    const ModalKinematics k =
        decode_modal_kinematics(c, static_cast<Command>(rows[i].cmd), payload.data(), payload.size());
    const auto sent = encode_modal_loads(c, static_cast<Command>(answer.cmd), peer_law(c, k));
    auto recorded = bytes_of(answer.values);
    recorded.insert(recorded.begin(), static_cast<std::uint8_t>(answer.cmd));
    mismatches += sent != recorded;
    ++answers;
  }
  return mismatches;
}

ModalConfig all2{ModalType::All, 2};

}  // namespace

TEST(ModalMessage, SizesAndFlagsOfTheThreeTypes) {
  EXPECT_EQ(all2.kinematics_payload_bytes(), 176u);
  EXPECT_EQ(all2.loads_payload_bytes(), 64u);
  EXPECT_EQ((ModalConfig{ModalType::Rigid, 2}.kinematics_payload_bytes()), 144u);
  EXPECT_EQ((ModalConfig{ModalType::Modal, 2}.kinematics_payload_bytes()), 32u);
  EXPECT_EQ((ModalConfig{ModalType::Rigid, 2}.loads_payload_bytes()), 48u);
  EXPECT_EQ((ModalConfig{ModalType::Modal, 2}.loads_payload_bytes()), 16u);
}

TEST(ModalMessage, NegotiationBytesAsRecorded) {
  const struct { const char* file; ModalType type; } cases[] = {
      {"transcript_loose.csv", ModalType::All}, {"transcript_tight.csv", ModalType::All},
      {"transcript_modal_type_rigid.csv", ModalType::Rigid}, {"transcript_modal_type_modal.csv", ModalType::Modal}};
  for (const auto& c : cases) {
    const auto rows = read_transcript(c.file);
    ASSERT_EQ(rows[0].cmd, 7);
    ASSERT_EQ(rows[1].cmd, 8);  // MBDyn accepted what the recording peer sent
    const ModalConfig config{c.type, 2};
    const auto bytes = modal_negotiation_request_bytes(config);
    std::uint32_t flags, n;
    std::memcpy(&flags, &bytes[1], 4);
    std::memcpy(&n, &bytes[5], 4);
    EXPECT_EQ(bytes[0], 7);
    EXPECT_EQ(flags, static_cast<std::uint32_t>(rows[0].values[0])) << c.file;
    EXPECT_EQ(n, static_cast<std::uint32_t>(rows[0].values[1])) << c.file;
    EXPECT_EQ(describe_modal_mismatch(config, flags, n), "");
  }
}

TEST(ModalMessage, MismatchesAreNamed) {
  EXPECT_NE(describe_modal_mismatch(all2, 0x5, 3).find("wrong mode count: MBDyn announces N=3"), std::string::npos);
  EXPECT_NE(describe_modal_mismatch(all2, 0x1, 2).find("rigid part mismatch"), std::string::npos);
  EXPECT_NE(describe_modal_mismatch(all2, 0x206, 2).find("nodal element"), std::string::npos);
  EXPECT_THROW(modal_type_from_name("both"), std::invalid_argument);
  EXPECT_EQ(modal_type_from_name("rigid"), ModalType::Rigid);
}

TEST(ModalMessage, FirstTightMessageDecodesColumnMajor) {
  const auto rows = read_transcript("transcript_tight.csv");
  const auto payload = bytes_of(rows[2].values);
  const ModalKinematics k = decode_modal_kinematics(all2, Command::RegularData, payload.data(), payload.size());
  EXPECT_EQ(k.x[2], 0.0002);
  EXPECT_EQ(k.R[3], 0.0003999999840000006);   // R21, second on the wire
  EXPECT_EQ(k.R[1], -0.0003999999840000006);  // R12, fourth on the wire
  EXPECT_EQ(k.v[2], 0.1);
  EXPECT_EQ(k.omega[2], 0.19999999200000032);
  EXPECT_EQ(k.q, (std::vector<double>{0.02, -0.01}));
  EXPECT_EQ(k.qdot, (std::vector<double>{0.0, 0.0}));
}

TEST(ModalMessage, RecordedAnswersReproducedBitForBit) {
  const struct { const char* file; ModalType type; } cases[] = {
      {"transcript_loose.csv", ModalType::All}, {"transcript_tight.csv", ModalType::All},
      {"transcript_modal_type_rigid.csv", ModalType::Rigid}, {"transcript_modal_type_modal.csv", ModalType::Modal}};
  for (const auto& c : cases) {
    int answers = 0;
    EXPECT_EQ(replay(ModalConfig{c.type, 2}, read_transcript(c.file), answers), 0) << c.file;
    EXPECT_GE(answers, 6) << c.file;
  }
}

TEST(ModalMessage, SwappedFieldOrderFailsAgainstTheRecording) {
  const auto rows = read_transcript("transcript_loose.csv");
  int answers = 0;
  // v and omega exchanged (doubles 12..14 and 15..17)
  const int swapped_v = replay(all2, rows, answers, [](std::vector<double>& w) {
    std::swap_ranges(w.begin() + 12, w.begin() + 15, w.begin() + 15);
  });
  EXPECT_GT(swapped_v, answers / 2);
  // R taken as row-major: the transpose on the wire
  const int transposed = replay(all2, rows, answers, [](std::vector<double>& w) {
    std::swap(w[4], w[6]); std::swap(w[5], w[9]); std::swap(w[8], w[10]);
  });
  EXPECT_GT(transposed, answers / 2);
  // q and qdot exchanged
  const int swapped_q = replay(all2, rows, answers, [](std::vector<double>& w) {
    std::swap_ranges(w.begin() + 18, w.begin() + 20, w.begin() + 20);
  });
  EXPECT_GT(swapped_q, answers / 2);
}

TEST(ModalMessage, LoadsInWireOrder) {
  ModalLoads l{{1, 2, 3}, {4, 5, 6}, {7, 8}};
  const auto b = encode_modal_loads(all2, Command::RegularDataAndGotoNextStep, l);
  ASSERT_EQ(b.size(), 65u);
  EXPECT_EQ(b[0], 6);
  double v[8];
  std::memcpy(v, &b[1], 64);
  for (int i = 0; i < 8; ++i) EXPECT_EQ(v[i], i + 1.0);
  const auto m = encode_modal_loads(ModalConfig{ModalType::Modal, 2}, Command::RegularData, l);
  ASSERT_EQ(m.size(), 17u);
  std::memcpy(v, &m[1], 16);
  EXPECT_EQ(v[0], 7.0);
  EXPECT_EQ(v[1], 8.0);
}

TEST(ModalMessage, BadMessagesRefused) {
  std::vector<std::uint8_t> short_payload(168);
  try {
    decode_modal_kinematics(all2, Command::RegularData, short_payload.data(), short_payload.size());
    FAIL();
  } catch (const MalformedMessageError& e) {
    EXPECT_NE(std::string(e.what()).find("expected 176 bytes"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("received 168"), std::string::npos) << e.what();
  }
  std::vector<double> w(22, 0.0);
  w[19] = std::nan("");
  const auto payload = bytes_of(w);
  try {
    decode_modal_kinematics(all2, Command::RegularData, payload.data(), payload.size());
    FAIL();
  } catch (const MalformedMessageError& e) {
    EXPECT_NE(std::string(e.what()).find("field 'q', component 1"), std::string::npos) << e.what();
  }
  ModalLoads one_mode{{}, {}, {1.0}};
  EXPECT_THROW(encode_modal_loads(all2, Command::RegularData, one_mode), std::invalid_argument);
  ModalLoads bad{{0, INFINITY, 0}, {}, {0, 0}};
  EXPECT_THROW(encode_modal_loads(all2, Command::RegularData, bad), MalformedMessageError);
  EXPECT_THROW(encode_modal_loads(all2, Command::GotoNextStep, ModalLoads{{}, {}, {0, 0}}), std::invalid_argument);
}
