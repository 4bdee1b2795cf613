// libFuzzer target: scene files with --set overrides (FuzzEntries.h, SceneJson).
#include "tests/fuzz/FuzzEntries.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  vkr::fuzz::SceneJson({data, size});
  return 0;
}
