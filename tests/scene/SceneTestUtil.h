#pragma once
// Shared helpers for the scene tests: a scene folder in a TempDir, tiny PGM images, and an
// assertion that a call fails with one InputError line naming file, path and problem.

#include <gtest/gtest.h>

#include <functional>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "engine/common/InputError.h"
#include "engine/scene/Scene.h"
#include "tests/common/TestFiles.h"

namespace vkr::test {

using Json = nlohmann::ordered_json;

// A valid scene: two parameters used by a box on a ground plane, no cameras.
inline Json BaseScene() {
  return Json::parse(R"({
    "version": 1,
    "parameters": {
      "w": {"prior": {"uniform": [0.5, 1.5]}},
      "h": {"prior": {"uniform": [0.2, 1.0]}, "init": 0.5}
    },
    "nodes": [
      {"name": "ground", "primitive": "plane", "transforms": [{"scale": [4, 4, 1]}]},
      {"name": "box", "primitive": "box", "transforms": [{"scale": ["w", 1, "h"]}]}
    ]
  })");
}

// A camera 4×3 pixels looking down +z from 5 m, for images written by WritePgm.
inline Json BaseCamera(const std::string& name, const std::string& image) {
  return Json{{"name", name}, {"image", image}, {"width", 4}, {"height", 3},
              {"K", {{2, 0, 2}, {0, 2, 1.5}, {0, 0, 1}}},
              {"R", {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}}}, {"t", {0, 0, 5}}};
}

// A binary PGM of width × height grey pixels.
inline void WritePgm(const std::filesystem::path& file, int width, int height) {
  WriteText(file, "P5\n" + std::to_string(width) + " " + std::to_string(height) + "\n255\n" +
                      std::string(size_t(width * height), '\x80'));
}

// Writes `scene` as dir/scene.json and returns its path.
inline std::filesystem::path WriteScene(const TempDir& dir, const Json& scene,
                                        const std::string& name = "scene.json") {
  const auto file = dir / name;
  WriteText(file, scene.dump(2));
  return file;
}

// Passes if `f` throws InputError whose message is one line containing every part.
inline ::testing::AssertionResult FailsWith(const std::function<void()>& f,
                                            const std::vector<std::string>& parts) {
  try {
    f();
  } catch (const InputError& e) {
    const std::string message = e.what();
    if (message.find('\n') != std::string::npos)
      return ::testing::AssertionFailure() << "message has several lines: " << message;
    for (const std::string& part : parts)
      if (message.find(part) == std::string::npos)
        return ::testing::AssertionFailure() << "message lacks '" << part << "': " << message;
    return ::testing::AssertionSuccess() << message;
  } catch (const std::exception& e) {
    return ::testing::AssertionFailure() << "threw a non-InputError: " << e.what();
  }
  return ::testing::AssertionFailure() << "did not throw";
}

// LoadScene of `scene` written into `dir` fails with all `parts` (and names scene.json).
inline ::testing::AssertionResult LoadFails(const TempDir& dir, const Json& scene,
                                            std::vector<std::string> parts,
                                            const std::vector<SceneOverride>& overrides = {}) {
  const auto file = WriteScene(dir, scene);
  parts.push_back("scene.json");
  return FailsWith([&] { LoadScene(file, overrides); }, parts);
}

}  // namespace vkr::test
