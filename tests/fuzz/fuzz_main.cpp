// One libFuzzer executable per target: SVO_FUZZ_TARGET names the function
// of fuzz_targets.h (tests/fuzz/CMakeLists.txt, Clang builds only).
#include "fuzz_targets.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  svo::fuzz::SVO_FUZZ_TARGET(data, size);
  return 0;
}
