// svo_fuzz_seeds DIR: writes the seed corpora into DIR/<target>/ (scripts/fuzz.sh).
#include <cstdio>
#include <exception>

#include "fuzz_targets.h"

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: %s DIR\n", argv[0]);
    return 2;
  }
  try {
    int n = svo::fuzz::write_seeds(argv[1]);
    std::printf("%d seeds in %s\n", n, argv[1]);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "svo_fuzz_seeds: %s\n", e.what());
    return 1;
  }
  return 0;
}
