// libFuzzer target: camera files (FuzzEntries.h, CameraFile).
#include "tests/fuzz/FuzzEntries.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  vkr::fuzz::CameraFile({data, size});
  return 0;
}
