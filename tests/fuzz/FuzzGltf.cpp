// libFuzzer target: glTF meshes (FuzzEntries.h, Gltf).
#include "tests/fuzz/FuzzEntries.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  vkr::fuzz::Gltf({data, size});
  return 0;
}
