// The fuzz targets' bodies run by every build (label: fuzz): the seed
// corpora are accepted inputs, and every input that once broke a target
// (regressions/<target>/<expected>-<name>, expected "accepted" or
// "refused") gives its expected outcome, with the sanitizers silent.
#include <gtest/gtest.h>

#include <fstream>

#include "fuzz_targets.h"
#include "render/temp_dir.h"

// tests/fuzz/allocation_cap.cpp: the largest operator new since the last call.
size_t svo_fuzz_largest_allocation_and_reset();

namespace {

namespace fs = std::filesystem;

std::vector<uint8_t> bytes_of(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

TEST(Fuzz, SeedCorporaAreAcceptedInputs) {
  svo::testing::TempDir dir;
  const int written = svo::fuzz::write_seeds(dir.path());
  EXPECT_GE(written, 20);
  int seen = 0;
  for (const std::string& target : svo::fuzz::target_names()) {
    ASSERT_TRUE(fs::is_directory(dir.path() / target)) << target;
    for (const auto& entry : fs::directory_iterator(dir.path() / target)) {
      auto bytes = bytes_of(entry.path());
      // The version 1 file and the refused-* seeds are seeds for the checks: refused.
      const std::string name = entry.path().filename().string();
      const int expected = name == "version1.svo" || name.rfind("refused-", 0) == 0 ? 0 : 1;
      EXPECT_EQ(svo::fuzz::run_target(target, bytes.data(), bytes.size()), expected) << entry.path();
      ++seen;
    }
  }
  EXPECT_EQ(seen, written);
}

// Deterministic mutations of the seeds (bytes overwritten, truncations):
// the contract holds (a crash or a sanitizer report fails the test).
TEST(Fuzz, MutatedSeedsAreRefusedOrAccepted) {
  svo::testing::TempDir dir;
  svo::fuzz::write_seeds(dir.path());
  uint64_t state = 0x9e3779b97f4a7c15ull;
  auto next = [&] {
    state ^= state << 13, state ^= state >> 7, state ^= state << 17;
    return state;
  };
  int refused = 0, runs = 0;
  for (const std::string& target : svo::fuzz::target_names()) {
    for (const auto& entry : fs::directory_iterator(dir.path() / target)) {
      const auto seed = bytes_of(entry.path());
      for (int trial = 0; trial < 12; ++trial) {
        auto bytes = seed;
        if (trial % 4 == 3) {
          bytes.resize(next() % (bytes.size() + 1));
        } else {
          for (int k = 0; k < 1 + trial % 3 && bytes.size() > 2; ++k)
            bytes[2 + next() % (bytes.size() - 2)] = uint8_t(next());
        }
        refused += svo::fuzz::run_target(target, bytes.data(), bytes.size()) == 0;
        ++runs;
      }
    }
  }
  EXPECT_GT(refused, 0) << "no mutation was refused: the checks did not run";
  EXPECT_LT(refused, runs);
}

TEST(Fuzz, RegressionInputsGiveTheirOutcome) {
  const fs::path root = SVO_FUZZ_REGRESSIONS;
  int seen = 0;
  for (const std::string& target : svo::fuzz::target_names()) {
    if (!fs::is_directory(root / target)) continue;
    for (const auto& entry : fs::directory_iterator(root / target)) {
      const std::string name = entry.path().filename().string();
      const bool accepted = name.rfind("accepted-", 0) == 0;
      ASSERT_TRUE(accepted || name.rfind("refused-", 0) == 0) << "name must start accepted- or refused-: " << name;
      auto bytes = bytes_of(entry.path());
      svo_fuzz_largest_allocation_and_reset();
      EXPECT_EQ(svo::fuzz::run_target(target, bytes.data(), bytes.size()), accepted ? 1 : 0) << entry.path();
      // Bounded memory: every input here is at most a few kilobytes, and the
      // pixels its header may state (at most 1111111 x 4 RGB, 53 MB) are
      // bounded by the budgets; a buffer sized by anything else is a finding.
      EXPECT_LE(svo_fuzz_largest_allocation_and_reset(), size_t(256) << 20) << entry.path();
      ++seen;
    }
  }
  std::printf("%d regression inputs\n", seen);
}

}  // namespace
