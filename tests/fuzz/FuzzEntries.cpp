#include "tests/fuzz/FuzzEntries.h"

#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "engine/common/InputError.h"
#include "engine/geometry/Mesh.h"
#include "engine/image/Image.h"
#include "engine/scene/Colmap.h"
#include "engine/scene/Scene.h"
#include "optimiser/Sampler.h"
#include "optimiser/Target.h"

namespace vkr::fuzz {
namespace {

namespace fs = std::filesystem;

// This process's scratch folder, removed at exit (not after a crash: libFuzzer then exits
// at once; scripts/fuzz.sh points $TMPDIR into its work folder for that reason).
class Scratch {
 public:
  Scratch() : dir_(fs::temp_directory_path() / ("vkrecon-fuzz-" + std::to_string(getpid()))) {
    fs::create_directories(dir_);
  }
  ~Scratch() {
    std::error_code ec;
    fs::remove_all(dir_, ec);
  }
  const fs::path& dir() const { return dir_; }

 private:
  fs::path dir_;
};

const fs::path& ScratchDir() {
  static const Scratch scratch;
  return scratch.dir();
}

void Write(const fs::path& file, std::string_view bytes) {
  fs::create_directories(file.parent_path());
  std::ofstream out(file, std::ios::binary | std::ios::trunc);
  out.write(bytes.data(), std::streamsize(bytes.size()));
  if (!out.flush()) throw std::runtime_error("fuzz: cannot write " + file.string());
}

std::string_view Text(Bytes input) {
  return {reinterpret_cast<const char*>(input.data()), input.size()};
}

// `text` cut at NUL bytes: the first part, then the others.
std::vector<std::string> SplitAtNul(std::string_view text) {
  std::vector<std::string> parts;
  for (size_t begin = 0;;) {
    const size_t end = text.find('\0', begin);
    parts.emplace_back(text.substr(begin, end == std::string_view::npos ? end : end - begin));
    if (end == std::string_view::npos) return parts;
    begin = end + 1;
  }
}

thread_local std::string g_last_refusal;

Outcome Refuse(const std::exception& e) {
  g_last_refusal = e.what();
  return Outcome::Refused;
}

// Runs `read`; the documented bad-input exception means Refused, everything else escapes.
template <typename Read>
Outcome Guard(Read read) {
  try {
    read();
    return Outcome::Accepted;
  } catch (const InputError& e) {
    return Refuse(e);
  }
}

// A scene with two parameters for `--at` files: one uniform, one normal with bounds.
constexpr const char* kAtScene = R"({
  "version": 1,
  "parameters": {
    "w": {"prior": {"uniform": [0.5, 2]}},
    "yaw": {"prior": {"normal": [0, 10]}, "bounds": [-45, 45]}
  },
  "nodes": [{"name": "box", "primitive": "box",
             "transforms": [{"rotate": [0, 0, "yaw"]}, {"scale": ["w", 1, 1]}]}]
})";

// A scene whose cameras come from cameras.json; `f` is there for K to use.
constexpr const char* kCameraScene = R"({
  "version": 1,
  "cameras": "cameras.json",
  "parameters": {"f": {"prior": {"uniform": [100, 1000]}}},
  "nodes": [{"name": "box", "primitive": "box", "transforms": [{"scale": ["f/500", 1, 1]}]}]
})";

// Scenes are loaded as `vkrecon synth` loads them (images not yet there): image files are
// fuzzed on their own, and a scene in the scratch folder has none beside it.
const LoadOptions kNoImages{.require_images = false};

}  // namespace

Outcome SceneJson(Bytes input) {
  const std::vector<std::string> parts = SplitAtNul(Text(input));
  const fs::path file = ScratchDir() / "scene" / "scene.json";
  Write(file, parts[0]);
  return Guard([&] {
    const std::vector<std::string> sets(parts.begin() + 1, parts.end());
    LoadScene(file, ParseOverrides(sets), kNoImages);
  });
}

Outcome AtValues(Bytes input) {
  static const Scene scene = [] {
    const fs::path file = ScratchDir() / "at" / "scene.json";
    Write(file, kAtScene);
    return LoadScene(file);
  }();
  const fs::path file = ScratchDir() / "at" / "at.json";
  Write(file, Text(input));
  return Guard([&] { scene.ValuesFromFile(file); });
}

Outcome CameraFile(Bytes input) {
  const fs::path dir = ScratchDir() / "cameras";
  static const bool scene_written = (Write(dir / "scene.json", kCameraScene), true);
  (void)scene_written;
  Write(dir / "cameras.json", Text(input));
  return Guard([&] { LoadScene(dir / "scene.json", {}, kNoImages); });
}

Outcome Colmap(Bytes input) {
  const std::string_view text = Text(input);
  const size_t cut = std::min(text.find('\0'), text.size());
  const fs::path dir = ScratchDir() / "sparse";
  Write(dir / "cameras.txt", text.substr(0, cut));
  Write(dir / "images.txt", cut < text.size() ? text.substr(cut + 1) : std::string_view());
  return Guard([&] { ReadColmapText(dir, "sparse"); });
}

// A valid binary model of one PINHOLE camera, one image "a.png" and one point, so that the
// fuzzed file is read past the files before it.
std::string ValidColmapBinary(int file) {
  const auto put = [](std::string& out, const auto& value) {
    out.append(reinterpret_cast<const char*>(&value), sizeof value);
  };
  std::string bytes;
  put(bytes, uint64_t(1));
  if (file == 0) {
    put(bytes, uint32_t(1)), put(bytes, int32_t(1)), put(bytes, uint64_t(4)), put(bytes, uint64_t(3));
    for (double v : {2.0, 2.0, 2.0, 1.5}) put(bytes, v);
  } else if (file == 1) {
    put(bytes, uint32_t(1));
    for (double v : {1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 5.0}) put(bytes, v);
    put(bytes, uint32_t(1));
    bytes.append("a.png", 6);
    put(bytes, uint64_t(0));
  } else {
    put(bytes, uint64_t(7));
    for (double v : {0.0, 0.0, 1.0}) put(bytes, v);
    bytes.append("\x01\x02\x03", 3);
    put(bytes, 0.5), put(bytes, uint64_t(1)), put(bytes, uint32_t(1)), put(bytes, uint32_t(0));
  }
  return bytes;
}

Outcome ColmapBinary(Bytes input) {
  const fs::path dir = ScratchDir() / "sparse_bin";
  const int fuzzed = input.empty() ? 0 : input[0] % 3;
  const char* names[] = {"cameras.bin", "images.bin", "points3D.bin"};
  for (int file = 0; file < 3; ++file)
    Write(dir / names[file], file == fuzzed ? Text(input.subspan(input.empty() ? 0 : 1)) : ValidColmapBinary(file));
  return Guard([&] { ReadColmapBinary(dir, "sparse"); });
}

Outcome Image(Bytes input) {
  const fs::path file = ScratchDir() / "image";
  Write(file, Text(input));
  int width = 0, height = 0;
  const Outcome size = Guard([&] { ReadImageSize(file, &width, &height); });
  vkr::Image image;
  const Outcome load = Guard([&] { image = LoadImage(file); });
  // A scene checks images by their header's size and loads them later: the two readers
  // must agree on every image they both accept.
  if (size == Outcome::Accepted && load == Outcome::Accepted &&
      (image.width != width || image.height != height))
    throw std::logic_error("ReadImageSize says " + std::to_string(width) + "x" +
                           std::to_string(height) + ", LoadImage gives " +
                           std::to_string(image.width) + "x" + std::to_string(image.height));
  return load;
}

Outcome Gltf(Bytes input) {
  const bool binary = Text(input).starts_with("glTF");
  const fs::path file = ScratchDir() / (binary ? "mesh.glb" : "mesh.gltf");
  Write(file, Text(input));
  return Guard([&] { LoadGltfMesh(file); });
}

Outcome Checkpoint(Bytes input) {
  // recon/Reconstruct.cpp reads the file into JSON and builds the sampler from it, and turns
  // the JSON parser's errors and the sampler's std::invalid_argument into InputError.
  nlohmann::json state;
  try {
    state = nlohmann::json::parse(Text(input));
  } catch (const nlohmann::json::exception& e) {
    return Refuse(e);
  }
  // A likelihood with the levels the checkpoint asks for (a real run refuses a mismatch,
  // which would stop the fuzzer at the first check), a flat log-likelihood and the batch of
  // a large scene.
  int levels = 1;
  if (state.is_object() && state.contains("target_levels") && state["target_levels"].is_number_integer())
    levels = int(std::clamp<int64_t>(state["target_levels"].get<int64_t>(), 1, 8));
  opt::FunctionTarget target([](const std::vector<double>&, int) { return 0.0; }, 64, levels);
  try {
    opt::Sampler sampler(state, target);
    if (!sampler.done()) sampler.Step();
    sampler.Checkpoint();
    return Outcome::Accepted;
  } catch (const std::invalid_argument& e) {
    return Refuse(e);
  }
}

const std::string& LastRefusal() { return g_last_refusal; }

std::span<const Entry> Entries() {
  static constexpr Entry kEntries[] = {
      {"scene_json", &SceneJson}, {"at_values", &AtValues}, {"camera_file", &CameraFile},
      {"colmap", &Colmap},        {"image", &Image},        {"gltf", &Gltf},
      {"checkpoint", &Checkpoint}, {"colmap_binary", &ColmapBinary},
  };
  return kEntries;
}

}  // namespace vkr::fuzz
