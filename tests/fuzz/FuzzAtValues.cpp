// libFuzzer target: --at parameter value files (FuzzEntries.h, AtValues).
#include "tests/fuzz/FuzzEntries.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  vkr::fuzz::AtValues({data, size});
  return 0;
}
