// libFuzzer target: sampler checkpoints (FuzzEntries.h, Checkpoint).
#include "tests/fuzz/FuzzEntries.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  vkr::fuzz::Checkpoint({data, size});
  return 0;
}
