// Checkpoint / resume: a run interrupted after a checkpoint and resumed from it (through
// the JSON text, by a new sampler on a new target) ends with exactly the chain and result
// of an uninterrupted run, whichever phase it was interrupted in.

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "optimiser/Sampler.h"
#include "tests/optimiser/Targets.h"

namespace vkr::opt::test {
namespace {

// A smooth 3-D target whose coarse levels are wider (like a blurred pyramid).
double LevelledTarget(const std::vector<double>& x, int level) {
  const double s = 1.0 + level;
  const double a = (x[0] - 0.4) / (0.3 * s), b = (x[1] + 0.2 * x[0]) / (0.5 * s),
               c = (x[2] - 1.0) / (0.8 * s);
  return -0.5 * (a * a + b * b + c * c) - 0.3 * std::sin(3.0 * x[2]);
}

std::vector<ParameterSpec> Parameters() {
  ParameterSpec n;
  n.name = "c";
  n.prior = PriorKind::Normal;
  n.a = 1.0;
  n.b = 2.0;
  n.bounds = std::make_pair(-3.0, 6.0);
  return {Uniform("a", -2, 2), Uniform("b", -3, 3, 0.5), n};
}

SamplerOptions Options() {
  SamplerOptions o;
  o.iterations = 300;
  o.until_converged = false;
  o.chains = 3;
  o.temperatures = 3;
  o.init_jitter = 0.05;
  o.adapt_min_samples = 10;
  o.refine_steps = 8;
  o.settle_steps = 2;  // leaves the final refinement steps to interrupt
  o.seed = 99;
  return o;
}

void ExpectSameSummary(const SamplerSummary& a, const SamplerSummary& b) {
  EXPECT_EQ(a.termination, b.termination);
  EXPECT_TRUE(SameChain(a.chain, b.chain));
  ASSERT_EQ(a.map.size(), b.map.size());
  for (size_t i = 0; i < a.map.size(); ++i) EXPECT_TRUE(Same(a.map[i], b.map[i]));
  EXPECT_TRUE(Same(a.map_log_posterior, b.map_log_posterior));
  EXPECT_TRUE(Same(a.sampling_map_log_posterior, b.sampling_map_log_posterior));
  EXPECT_EQ(a.frames, b.frames);
  EXPECT_EQ(a.evaluations, b.evaluations);
  EXPECT_EQ(a.refine_steps, b.refine_steps);
  // Every statistic, through the text of map.json (full precision).
  EXPECT_EQ(MapJson(a).dump(), MapJson(b).dump());
}

TEST(Checkpoint, ResumedRunIsBitIdentical) {
  FunctionTarget straight_target(LevelledTarget, 9, 3);
  SamplerSummary straight;
  ASSERT_TRUE(opt::Run(Options(), Parameters(), straight_target, &straight)) << straight.message;
  ASSERT_GT(straight.refine_steps, 2);
  const int64_t frames = straight.frames;

  // Interrupt in the start phase, just after a level change, mid-sampling, at the last
  // sampling frame and inside the refinement.
  const int64_t refine_start = frames - straight.refine_steps;
  for (int64_t stop_at : {int64_t(1), int64_t(32), int64_t(33), frames / 2, refine_start,
                          refine_start + 2}) {
    SCOPED_TRACE(stop_at);
    std::string text;
    {
      FunctionTarget target(LevelledTarget, 9, 3);
      SamplerCallbacks callbacks;
      callbacks.on_frame = [&](const Progress& p) {
        FrameRequest r;
        r.checkpoint = r.stop = p.frame == stop_at;
        return r;
      };
      callbacks.on_checkpoint = [&](const nlohmann::json& j) { text = j.dump(); };
      SamplerSummary partial;
      EXPECT_FALSE(opt::Run(Options(), Parameters(), target, &partial, callbacks));
      EXPECT_EQ(partial.termination, Termination::Stopped);
      EXPECT_EQ(partial.frames, stop_at);
    }
    ASSERT_FALSE(text.empty());
    const nlohmann::json checkpoint = nlohmann::json::parse(text);
    EXPECT_EQ(checkpoint.dump(), text);  // numbers survive the text exactly

    FunctionTarget target(LevelledTarget, 9, 3);
    SamplerSummary resumed;
    ASSERT_TRUE(Resume(checkpoint, target, &resumed)) << resumed.message;
    ExpectSameSummary(straight, resumed);
  }
}

TEST(Checkpoint, CheckpointBeforeTheFirstFrameAndStepByStep) {
  FunctionTarget a_target(LevelledTarget, 9, 3), b_target(LevelledTarget, 9, 3);
  Sampler a(Options(), Parameters(), a_target);
  auto b = std::make_unique<Sampler>(a.Checkpoint(), b_target);
  int frame = 0;
  while (!a.done()) {
    a.Step();
    b->Step();
    if (++frame % 50 == 0) {  // hand over to a fresh sampler every 50 frames
      const nlohmann::json j = nlohmann::json::parse(b->Checkpoint().dump());
      b.reset();
      b = std::make_unique<Sampler>(j, b_target);
    }
  }
  EXPECT_TRUE(b->done());
  ExpectSameSummary(a.Summary(), b->Summary());
  EXPECT_EQ(a.Checkpoint().dump(), b->Checkpoint().dump());
}

// A checkpoint written before cooling and independence proposals (none of their fields)
// resumes as the run it was: tempered to the end, random walk only.
TEST(Checkpoint, CheckpointFromBeforeCoolingGoesOnAsItBegan) {
  SamplerOptions legacy = Options();
  legacy.cool_after_settling = false;
  legacy.independence_share = 0.0;
  FunctionTarget straight_target(LevelledTarget, 9, 3);
  SamplerSummary straight;
  ASSERT_TRUE(opt::Run(legacy, Parameters(), straight_target, &straight)) << straight.message;
  EXPECT_EQ(straight.posterior_chains, 3);

  FunctionTarget target(LevelledTarget, 9, 3);
  Sampler sampler(legacy, Parameters(), target);
  while (sampler.progress().iteration < 200) sampler.Step();
  nlohmann::json old = sampler.Checkpoint();
  old["options"].erase("cool_after_settling");
  old["options"].erase("independence_share");
  old["settle"].erase("mode");
  for (auto& chain : old["chains"])
    for (auto& replica : chain["replicas"]) {
      replica.erase("independent_proposed");
      replica.erase("independent_accepted");
    }
  FunctionTarget resumed_target(LevelledTarget, 9, 3);
  SamplerSummary resumed;
  ASSERT_TRUE(Resume(old, resumed_target, &resumed)) << resumed.message;
  ExpectSameSummary(straight, resumed);
}

// A checkpoint written before posterior_chains (every cooled replica sampled on) resumes
// with all of them, mid-run after cooling as before it.
TEST(Checkpoint, CheckpointFromBeforePosteriorChainsKeepsEveryReplica) {
  SamplerOptions all = Options();
  all.posterior_chains = 0;
  FunctionTarget straight_target(LevelledTarget, 9, 3);
  SamplerSummary straight;
  ASSERT_TRUE(opt::Run(all, Parameters(), straight_target, &straight)) << straight.message;
  EXPECT_EQ(straight.posterior_chains, 9);
  for (const int at : {100, 250}) {
    SCOPED_TRACE(at);
    FunctionTarget target(LevelledTarget, 9, 3);
    Sampler sampler(all, Parameters(), target);
    while (sampler.progress().iteration < at) sampler.Step();
    nlohmann::json old = sampler.Checkpoint();
    old["options"].erase("posterior_chains");
    FunctionTarget resumed_target(LevelledTarget, 9, 3);
    SamplerSummary resumed;
    ASSERT_TRUE(Resume(old, resumed_target, &resumed)) << resumed.message;
    ExpectSameSummary(straight, resumed);
  }
}

TEST(Checkpoint, MismatchedOrMalformedCheckpointsAreRejected) {
  FunctionTarget target(LevelledTarget, 9, 3);
  Sampler sampler(Options(), Parameters(), target);
  for (int i = 0; i < 5; ++i) sampler.Step();
  const nlohmann::json good = sampler.Checkpoint();
  SamplerSummary s;

  FunctionTarget other_levels(LevelledTarget, 9, 2);
  EXPECT_FALSE(Resume(good, other_levels, &s));
  EXPECT_EQ(s.termination, Termination::Failed);
  EXPECT_NE(s.message.find("levels"), std::string::npos) << s.message;

  FunctionTarget small_batch(LevelledTarget, 4, 3);
  EXPECT_FALSE(Resume(good, small_batch, &s));
  EXPECT_NE(s.message.find("batch"), std::string::npos) << s.message;

  nlohmann::json bad = good;
  bad["chains"][0]["rng"] = "garbage";
  EXPECT_FALSE(Resume(bad, target, &s));
  EXPECT_NE(s.message.find("RNG"), std::string::npos) << s.message;
  bad = good;
  bad.erase("samples");
  EXPECT_FALSE(Resume(bad, target, &s));
  EXPECT_NE(s.message.find("checkpoint"), std::string::npos) << s.message;
  bad = good;
  bad["chains"][1]["replicas"][0]["psi"] = {1.0};
  EXPECT_FALSE(Resume(bad, target, &s));
  EXPECT_FALSE(Resume(nlohmann::json{{"format", "something else"}}, target, &s));
  EXPECT_THROW(Sampler(nlohmann::json::array(), target), std::invalid_argument);
  // Integers must be JSON integers in range: a float was cast to int, undefined beyond its
  // range (fuzz_checkpoint found target_levels 2.6e51).
  for (const nlohmann::json& value : {nlohmann::json(2.55556e51), nlohmann::json(3.0), nlohmann::json(4294967299LL)}) {
    bad = good;
    bad["target_levels"] = value;
    EXPECT_FALSE(Resume(bad, target, &s)) << value;
    EXPECT_NE(s.message.find("expected an integer"), std::string::npos) << s.message;
  }
}

}  // namespace
}  // namespace vkr::opt::test
