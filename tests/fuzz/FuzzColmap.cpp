// libFuzzer target: COLMAP text models (FuzzEntries.h, Colmap).
#include "tests/fuzz/FuzzEntries.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  vkr::fuzz::Colmap({data, size});
  return 0;
}
