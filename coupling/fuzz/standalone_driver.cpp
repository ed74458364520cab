// A minimal driver for LLVMFuzzerTestOneInput when libFuzzer is not available (gcc builds):
// valid messages of every configuration, then random mutations of them for a time budget.
// Usage: mbdyn_decoder_fuzz_smoke <seconds> [seed]
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <random>
#include <vector>

#include "nodal_config.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size);

int main(int argc, char** argv) {
  const double budget = argc > 1 ? std::atof(argv[1]) : 5.0;
  std::mt19937_64 rng(argc > 2 ? std::strtoull(argv[2], nullptr, 10) : 1);
  // Seeds: selector, N, negotiation answer 8, then kinematics messages of the exact size.
  std::vector<std::vector<std::uint8_t>> seeds;
  for (unsigned selector = 0; selector < 64; ++selector)
    for (unsigned n = 0; n < 5; ++n) {
      dembridge::mbdyn::NodalConfig c;
      static const dembridge::mbdyn::Rotation rot[4] = {
          dembridge::mbdyn::Rotation::None, dembridge::mbdyn::Rotation::OrientationVector,
          dembridge::mbdyn::Rotation::OrientationMatrix, dembridge::mbdyn::Rotation::Euler123};
      c.rotation = rot[selector & 3];
      c.labels = selector & 4;
      c.accelerations = selector & 8;
      c.reference_node = selector & 16;
      c.num_points = n;
      std::vector<std::uint8_t> s{static_cast<std::uint8_t>(selector), static_cast<std::uint8_t>(n), 8};
      for (int m = 0; m < 3; ++m) {
        s.push_back((selector & 32) ? 2 : 6);
        for (std::size_t b = 0; b < c.kinematics_payload_bytes(); ++b) s.push_back(0);
      }
      seeds.push_back(s);
    }
  std::size_t runs = 0;
  for (const auto& s : seeds) {
    LLVMFuzzerTestOneInput(s.data(), s.size());
    ++runs;
  }
  const auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(budget);
  while (std::chrono::steady_clock::now() < end) {
    std::vector<std::uint8_t> input = seeds[rng() % seeds.size()];
    const int edits = 1 + static_cast<int>(rng() % 8);
    for (int e = 0; e < edits && !input.empty(); ++e) {
      const std::size_t at = rng() % input.size();
      switch (rng() % 5) {
        case 0: input[at] = static_cast<std::uint8_t>(rng()); break;          // random byte
        case 1: input[at] ^= static_cast<std::uint8_t>(1u << (rng() % 8)); break;  // bit flip
        case 2: input.resize(at); break;                                     // truncate
        case 3: input.insert(input.begin() + static_cast<long>(at), static_cast<std::uint8_t>(rng())); break;
        case 4:                                                              // NaN/Inf bytes
          for (std::size_t k = at; k < input.size() && k < at + 8; ++k) input[k] = k + 1 == at + 8 ? 0x7f : 0xff;
          break;
      }
    }
    LLVMFuzzerTestOneInput(input.data(), input.size());
    ++runs;
  }
  std::printf("mbdyn_decoder_fuzz_smoke: %zu inputs in %.1f s, no failure\n", runs, budget);
  return 0;
}
