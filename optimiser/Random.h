#pragma once
// Random numbers whose sequence depends only on the seed. std::mt19937_64 is specified
// exactly by the standard, but std::uniform_real_distribution and std::normal_distribution
// are not (libstdc++, libc++ and MSVC give different numbers), so the transforms from raw
// 64-bit words to uniforms and normals are written here. Normals use Marsaglia's polar
// method, which needs only sqrt (exact in IEEE 754) and log (glibc's is accurate to the last
// bit in practice; another libm may differ in rare last bits).

#include <cstdint>
#include <random>
#include <string>

namespace vkr::opt {

class Rng {
 public:
  explicit Rng(uint64_t seed = 1) : engine_(seed) {}
  // A stream independent of the others of the same seed: the engine is seeded with
  // SplitMix64 of (seed, stream), so nearby seeds and streams do not overlap in practice.
  static Rng ForStream(uint64_t seed, uint64_t stream);

  uint64_t NextU64() { return engine_(); }
  double Uniform();      // [0, 1), 53 random bits
  double UniformOpen();  // (0, 1): safe to take the log of
  double Normal();       // standard normal; consumes two or more words

  // The engine's state as text (operator<< in the classic locale) and back. SetState
  // returns false for text that is not such a state.
  std::string State() const;
  bool SetState(const std::string& text);

  bool operator==(const Rng& other) const { return engine_ == other.engine_; }

 private:
  std::mt19937_64 engine_;
};

}  // namespace vkr::opt
