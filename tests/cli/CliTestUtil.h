#pragma once
// Shared by the command-line tests: shell quoting and the bad-input contract (exit status
// 2, one line on stderr naming file, field and problem).

#include <gtest/gtest.h>

#include <filesystem>
#include <string>
#include <vector>

#include "tests/common/TestFiles.h"

namespace vkr::test {

inline std::string Quote(const std::string& s) { return "'" + s + "'"; }
inline std::string Quote(const std::filesystem::path& p) { return Quote(p.string()); }

// Exit status 2 and exactly one line on stderr containing every `needle`.
inline void ExpectBadInput(const CommandResult& r, const std::vector<std::string>& needles) {
  EXPECT_EQ(r.exit_status, 2) << r.err;
  std::string err = r.err;
  while (!err.empty() && err.back() == '\n') err.pop_back();
  EXPECT_EQ(err.find('\n'), std::string::npos) << "more than one line:\n" << r.err;
  for (const auto& n : needles) EXPECT_NE(r.err.find(n), std::string::npos) << "missing '" << n << "' in: " << r.err;
}

#if defined(VKRECON_BINARY) && defined(VKRECON_SOURCE_DIR)
// Quarter-size images of the box asset at its truth in dir/images (`options` go to synth,
// e.g. " --noise 8"): the runs of RunCliTest and ScaleOutCliTest reconstruct them.
inline bool SynthBoxImages(const std::filesystem::path& dir, const std::string& options) {
  const std::filesystem::path box = std::filesystem::path(VKRECON_SOURCE_DIR) / "assets/box";
  return RunCommand(std::string(VKRECON_BINARY) + " synth -q " + Quote(box / "scene.json") + " --at " +
                    Quote(box / "truth.json") + " --scale 0.25" + options + " -o " + Quote(dir / "images"))
             .exit_status == 0;
}
#endif

}  // namespace vkr::test
