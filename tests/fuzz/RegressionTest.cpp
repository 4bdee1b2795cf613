// Replays the fuzzer's finds in the normal build: every input stored under
// tests/fuzz/regressions/<entry>/ once crashed, hung or tripped a sanitizer, and must now
// end in a clean bad-input error. The hand-made seeds of tests/fuzz/seeds/<entry>/ are
// valid inputs and must be accepted, which also proves each entry reaches its reader (an
// entry that refused everything, say for a broken scratch folder, would pass the replay
// vacuously).

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <ostream>
#include <string>
#include <vector>

#include "tests/fuzz/FuzzEntries.h"

namespace vkr::fuzz {

// For gtest's messages (found by argument-dependent lookup, so not in the unnamed namespace).
void PrintTo(Outcome outcome, std::ostream* out) {
  *out << (outcome == Outcome::Accepted ? "Accepted" : "Refused");
}

namespace {

namespace fs = std::filesystem;

const fs::path kFuzzDir = fs::path(VKRECON_SOURCE_DIR) / "tests" / "fuzz";

struct StoredInput {
  const Entry* entry;
  fs::path file;
};

// For gtest's messages: the file, not the bytes of the struct.
void PrintTo(const StoredInput& input, std::ostream* out) { *out << input.file.string(); }

// Every file of `folder`/<entry name>/, sorted, for each entry.
std::vector<StoredInput> Stored(const char* folder) {
  std::vector<StoredInput> inputs;
  for (const Entry& entry : Entries()) {
    const fs::path dir = kFuzzDir / folder / entry.name;
    if (!fs::is_directory(dir)) continue;
    std::vector<fs::path> files;
    for (const auto& f : fs::directory_iterator(dir))
      if (f.is_regular_file()) files.push_back(f.path());
    std::sort(files.begin(), files.end());
    for (const fs::path& f : files) inputs.push_back({&entry, f});
  }
  return inputs;
}

std::vector<uint8_t> ReadBytes(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

std::string TestName(const ::testing::TestParamInfo<StoredInput>& info) {
  std::string name = std::string(info.param.entry->name) + "_" + info.param.file.filename().string();
  std::replace_if(name.begin(), name.end(), [](char c) { return !std::isalnum(static_cast<unsigned char>(c)); }, '_');
  return name;
}

class Regression : public ::testing::TestWithParam<StoredInput> {};

TEST_P(Regression, EndsInACleanInputError) {
  const std::vector<uint8_t> bytes = ReadBytes(GetParam().file);
  ASSERT_EQ(bytes.size(), fs::file_size(GetParam().file)) << "cannot read " << GetParam().file;
  EXPECT_EQ(GetParam().entry->run(bytes), Outcome::Refused) << GetParam().file;
}

INSTANTIATE_TEST_SUITE_P(Fuzz, Regression, ::testing::ValuesIn(Stored("regressions")), TestName);
GTEST_ALLOW_UNINSTANTIATED_PARAMETERIZED_TEST(Regression);

class Seed : public ::testing::TestWithParam<StoredInput> {};

TEST_P(Seed, IsAccepted) {
  const std::vector<uint8_t> bytes = ReadBytes(GetParam().file);
  EXPECT_EQ(GetParam().entry->run(bytes), Outcome::Accepted) << LastRefusal();
}

INSTANTIATE_TEST_SUITE_P(Fuzz, Seed, ::testing::ValuesIn(Stored("seeds")), TestName);

TEST(Seed, EveryEntryHasOne) {
  const std::vector<StoredInput> seeds = Stored("seeds");
  for (const Entry& entry : Entries())
    EXPECT_TRUE(std::any_of(seeds.begin(), seeds.end(), [&](const StoredInput& s) { return s.entry == &entry; }))
        << "no seed in tests/fuzz/seeds/" << entry.name;
}

}  // namespace
}  // namespace vkr::fuzz
