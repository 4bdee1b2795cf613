#include "optimiser/Random.h"

#include <cmath>
#include <locale>
#include <sstream>

namespace vkr::opt {
namespace {

uint64_t SplitMix64(uint64_t x) {
  x += 0x9e3779b97f4a7c15ull;
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ull;
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebull;
  return x ^ (x >> 31);
}

constexpr double kTwoToMinus53 = 1.0 / 9007199254740992.0;

}  // namespace

Rng Rng::ForStream(uint64_t seed, uint64_t stream) {
  return Rng(SplitMix64(SplitMix64(seed) ^ (stream * 0xd1b54a32d192ed03ull + 1)));
}

double Rng::Uniform() { return double(engine_() >> 11) * kTwoToMinus53; }

double Rng::UniformOpen() { return (double(engine_() >> 11) + 0.5) * kTwoToMinus53; }

double Rng::Normal() {
  for (;;) {
    const double u = 2.0 * Uniform() - 1.0;
    const double v = 2.0 * Uniform() - 1.0;
    const double s = u * u + v * v;
    // The pair's second normal, v·f, is dropped: caching it would add state to checkpoints.
    if (s > 0.0 && s < 1.0) return u * std::sqrt(-2.0 * std::log(s) / s);
  }
}

std::string Rng::State() const {
  std::ostringstream out;
  out.imbue(std::locale::classic());
  out << engine_;
  return out.str();
}

bool Rng::SetState(const std::string& text) {
  std::istringstream in(text);
  in.imbue(std::locale::classic());
  std::mt19937_64 engine;
  in >> engine;
  if (in.fail()) return false;
  in >> std::ws;
  if (!in.eof()) return false;
  engine_ = engine;
  return true;
}

}  // namespace vkr::opt
