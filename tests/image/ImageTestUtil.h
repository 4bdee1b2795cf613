#pragma once
// Shared helpers of the image tests: error checks and small images with known content.

#include <gtest/gtest.h>

#include <filesystem>
#include <random>
#include <string>

#include "engine/common/InputError.h"
#include "engine/image/Image.h"

namespace vkr::test {

// Runs `action`, expecting an InputError whose one-line what() names `file` and contains
// `needle` (case-sensitive; empty to skip that check).
template <typename Action>
void ExpectInputError(Action action, const std::filesystem::path& file, const std::string& needle) {
  try {
    action();
    ADD_FAILURE() << "no InputError for " << file;
  } catch (const InputError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find(file.string()), std::string::npos) << what;
    EXPECT_EQ(what.find('\n'), std::string::npos) << what;
    if (!needle.empty()) {
      EXPECT_NE(what.find(needle), std::string::npos) << what;
    }
  } catch (const std::exception& e) {
    ADD_FAILURE() << "expected InputError, got: " << e.what();
  }
}

// An image whose every channel is k/255 for a random byte k.
inline Image RandomBytesImage(int w, int h, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_int_distribution<int> byte(0, 255);
  Image image(w, h);
  for (float& v : image.rgba) v = float(byte(rng)) / 255.0f;
  return image;
}

}  // namespace vkr::test
