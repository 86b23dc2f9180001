// libFuzzer target for the .svo loader (STYLE 9). The input's checksums are
// recomputed first, so that mutations reach the validation behind them.
// Contract under test: any bytes give either a tree that validate_octree
// accepts or a FileError; never a crash, a sanitizer report or another error.
// Built only with Clang (tests/CMakeLists.txt); run e.g.
//   build-clang/tests/svo_load_fuzz -max_total_time=60 CORPUS_DIR
#include <cstdint>
#include <vector>

#include "svo/octree/svo_file.h"
#include "svo_format.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  std::vector<uint8_t> bytes(data, data + size);  // aligned for SvoView
  if (bytes.size() >= svo::octree::format::kHeaderBytes) svo::octree::format::seal(bytes);
  try {
    svo::octree::SvoView view(bytes, "fuzz.svo");
    svo::octree::validate_octree(view.copy());
  } catch (const svo::octree::FileError&) {
  }
  return 0;
}
