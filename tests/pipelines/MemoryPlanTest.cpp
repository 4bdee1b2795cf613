// The memory plan (MemoryPlan.h) against what the likelihoods really allocate, and the
// refusals it gives before anything is allocated.

#include <gtest/gtest.h>

#include "engine/common/InputError.h"
#include "pipelines/likelihood/ImageLikelihood.h"
#include "pipelines/likelihood/MemoryPlan.h"
#include "pipelines/likelihood/SurfaceLikelihood.h"
#include "tests/common/GpuTest.h"
#include "tests/common/TestFiles.h"
#include "tests/pipelines/SynthesisedAsset.h"

namespace vkr {
namespace {

// The box asset at quarter size (160×120, 9 cameras), photographed once for the suite.
class MemoryPlanBox : public test::GpuTest {
 protected:
  static void SetUpTestSuite() {
    dir_ = new test::TempDir;
    std::vector<double> truth;
    scene_ = new Scene(test::SynthesisedScene(device(), "box", 0.0, *dir_, &truth));
  }
  static void TearDownTestSuite() {
    delete scene_;
    delete dir_;
    scene_ = nullptr;
    dir_ = nullptr;
  }
  static SurfaceLikelihoodOptions SurfaceOptions() {
    SurfaceLikelihoodOptions o = SurfaceLikelihoodOptions::FromScene(*scene_);
    o.atlas = 256;
    o.levels = 2;
    o.max_batch = 8;
    return o;
  }
  // What lavapipe offers: a 2 GiB heap, allocations up to the heap.
  static MemoryLimits TwoGiB() {
    MemoryLimits limits;
    limits.device_name = "a 2 GiB device";
    limits.heap = limits.max_allocation = uint64_t(2) << 30;
    return limits;
  }
  static test::TempDir* dir_;
  static Scene* scene_;
};
test::TempDir* MemoryPlanBox::dir_ = nullptr;
Scene* MemoryPlanBox::scene_ = nullptr;

// The plan is only worth its refusals if it counts what the constructors allocate: within
// 10 % (alignment and small buffers aside), or the limits it checks are fiction.
void ExpectClose(uint64_t planned, uint64_t allocated) {
  EXPECT_GT(allocated, 0u);
  EXPECT_GE(double(planned), 0.9 * double(allocated)) << FormatBytes(planned) << " planned, " << FormatBytes(allocated) << " allocated";
  EXPECT_LE(double(planned), 1.1 * double(allocated)) << FormatBytes(planned) << " planned, " << FormatBytes(allocated) << " allocated";
}

TEST_F(MemoryPlanBox, CountsWhatTheSurfaceLikelihoodAllocates) {
  for (int atlas : {256, 1024}) {
    SurfaceLikelihoodOptions options = SurfaceOptions();
    options.atlas = atlas;
    const uint64_t before = device().allocated_bytes();
    SurfaceLikelihood likelihood(device(), *scene_, options);
    ExpectClose(PlanSurfaceLikelihood(*scene_, options, device().subgroup_size()).device_total(),
                device().allocated_bytes() - before);
  }
}

TEST_F(MemoryPlanBox, CountsWhatTheImageLikelihoodAllocates) {
  ImageLikelihoodOptions options = ImageLikelihoodOptions::FromScene(*scene_);
  options.levels = 2;
  options.max_batch = 4;
  const uint64_t before = device().allocated_bytes();
  ImageLikelihood likelihood(device(), *scene_, options);
  ExpectClose(PlanImageLikelihood(*scene_, options, device().subgroup_size()).device_total(),
              device().allocated_bytes() - before);
}

TEST_F(MemoryPlanBox, TooLargeAnAtlasIsRefusedWithTheNumbersAndOneThatFits) {
  SurfaceLikelihoodOptions options = SurfaceOptions();
  options.atlas = 8192;
  options.levels = 3;
  try {
    RequireSurfaceLikelihoodFits(*scene_, options, TwoGiB(), 8);
    FAIL() << "an 8192² atlas for 9 cameras fitted in 2 GiB";
  } catch (const InputError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("likelihood.atlas"), std::string::npos) << what;
    EXPECT_NE(what.find("8192 with 9 cameras does not fit"), std::string::npos) << what;
    EXPECT_NE(what.find("view textures 9 × 8192² × 8 B = 4.5 GiB"), std::string::npos) << what;
    EXPECT_NE(what.find("but the device (a 2 GiB device) has 2.0 GiB"), std::string::npos) << what;
    // The atlas it proposes must itself fit, and the next larger one must not.
    const size_t at = what.find("an atlas of ");
    ASSERT_NE(at, std::string::npos) << what;
    options.atlas = std::stoi(what.substr(at + 12));
    EXPECT_TRUE(WhyItDoesNotFit(PlanSurfaceLikelihood(*scene_, options, 8), TwoGiB()).empty()) << what;
    options.atlas *= 2;
    EXPECT_FALSE(WhyItDoesNotFit(PlanSurfaceLikelihood(*scene_, options, 8), TwoGiB()).empty()) << what;
  }
}

TEST_F(MemoryPlanBox, ABatchThatCannotFitNamesTheBatch) {
  SurfaceLikelihoodOptions options = SurfaceOptions();
  options.max_batch = 4096;
  MemoryLimits limits = TwoGiB();
  limits.heap = uint64_t(64) << 20;
  try {
    RequireSurfaceLikelihoodFits(*scene_, options, limits, 8);
    FAIL() << "a batch of 4096 fitted in 64 MiB";
  } catch (const InputError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("sampler.batch"), std::string::npos) << what;
    EXPECT_NE(what.find("a batch of "), std::string::npos) << what;
  }
}

TEST_F(MemoryPlanBox, ACpuDeviceMustAlsoFitInTheHostsMemory) {
  MemoryLimits limits = TwoGiB();
  limits.device_memory_is_host = true;
  limits.host_available = uint64_t(1) << 20;
  EXPECT_NE(WhyItDoesNotFit(PlanSurfaceLikelihood(*scene_, SurfaceOptions(), 8), limits).find("is available"),
            std::string::npos);
  limits.device_memory_is_host = false;
  EXPECT_EQ(WhyItDoesNotFit(PlanSurfaceLikelihood(*scene_, SurfaceOptions(), 8), limits), "");
}

// On any device: an atlas no device holds is refused by the constructor before it allocates.
TEST_F(MemoryPlanBox, TheLikelihoodRefusesBeforeAllocatingAnything) {
  SurfaceLikelihoodOptions options = SurfaceOptions();
  options.atlas = 1 << 17;  // 9 × 2^34 texels × 8 B = 1.1 TiB of view textures
  const uint64_t before = device().allocated_bytes();
  EXPECT_THROW(SurfaceLikelihood(device(), *scene_, options), InputError);
  EXPECT_EQ(device().allocated_bytes(), before);
}

TEST(FormatBytes, PicksTheUnit) {
  EXPECT_EQ(FormatBytes(512), "512 B");
  EXPECT_EQ(FormatBytes(uint64_t(3) << 19), "1.5 MiB");
  EXPECT_EQ(FormatBytes(uint64_t(4831838208)), "4.5 GiB");
  EXPECT_EQ(FormatBytes(uint64_t(200) << 30), "200 GiB");
}

}  // namespace
}  // namespace vkr
