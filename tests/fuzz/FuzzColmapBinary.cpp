// libFuzzer target: COLMAP binary models (FuzzEntries.h, ColmapBinary).
#include "tests/fuzz/FuzzEntries.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  vkr::fuzz::ColmapBinary({data, size});
  return 0;
}
