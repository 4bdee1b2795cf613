#pragma once
// The fuzzed entry points of vkrecon's readers, shared by the libFuzzer targets of this
// folder (built with -DVKRECON_FUZZ=ON and clang) and by the GoogleTest that replays every
// input stored under tests/fuzz/regressions/ in the normal build. One place, so a
// regression test feeds its input through exactly the code the fuzzer found it with.
//
// Each entry writes the input where the reader expects a file (a scratch folder of this
// process under $TMPDIR) and calls the reader as the command line does. The documented bad
// input outcome (InputError; for checkpoints what `vkrecon run --resume` turns into one) is
// caught and reported as Refused. Anything else — a crash, a sanitizer report, an exception
// of another type escaping — is a bug in the reader.

#include <cstdint>
#include <span>
#include <string>
#include <string_view>

namespace vkr::fuzz {

enum class Outcome {
  Accepted,  // the reader took the input
  Refused,   // a clean bad-input error: one line naming file, field and problem
};

using Bytes = std::span<const uint8_t>;

// Scene file (scene.json) followed by `--set PATH=VALUE` overrides, each after a NUL byte.
Outcome SceneJson(Bytes input);
// A parameter value file (`--at P.json`, truth.json) for a fixed two-parameter scene.
Outcome AtValues(Bytes input);
// A camera file (`"cameras": "cameras.json"`) of a fixed scene with one parameter `f`.
Outcome CameraFile(Bytes input);
// A COLMAP text model: cameras.txt, a NUL byte, images.txt.
Outcome Colmap(Bytes input);
// A COLMAP binary model: the first byte picks the file the rest is (0: cameras.bin, 1:
// images.bin, 2: points3D.bin, modulo 3); the other two are a fixed valid model's.
Outcome ColmapBinary(Bytes input);
// An image file of any format (sniffed): ReadImageSize, then LoadImage.
Outcome Image(Bytes input);
// A glTF mesh: .glb when it starts with the binary magic "glTF", .gltf otherwise.
Outcome Gltf(Bytes input);
// A sampler checkpoint, read as `vkrecon run --resume` reads OUT/checkpoint.json, then
// continued for one frame.
Outcome Checkpoint(Bytes input);

// The message of the last Refused outcome of this thread, for test failures.
const std::string& LastRefusal();

// The entries by the names used for folders (regressions/<name>, seeds/<name>) and fuzz
// binaries (fuzz_<name>).
struct Entry {
  const char* name;
  Outcome (*run)(Bytes input);
};
std::span<const Entry> Entries();

}  // namespace vkr::fuzz
