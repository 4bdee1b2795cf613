// libFuzzer target: image files (PNG, JPEG, PGM, PPM, EXR) (FuzzEntries.h, Image).
#include "tests/fuzz/FuzzEntries.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  vkr::fuzz::Image({data, size});
  return 0;
}
