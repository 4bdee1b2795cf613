#include "pipelines/Environment.h"

#include <cmath>
#include <cstdint>

namespace vkr {
namespace {

// A hash of a lattice point to [0,1).
float Hash(int x, int y, int z) {
  uint32_t h = uint32_t(x) * 374761393u + uint32_t(y) * 668265263u + uint32_t(z) * 2147483647u;
  h = (h ^ (h >> 13)) * 1274126177u;
  return float((h ^ (h >> 16)) & 0xFFFFFFu) / float(0x1000000);
}

// Trilinear value noise with smoothstep weights.
float ValueNoise(const Eigen::Vector3d& p) {
  const int x0 = int(std::floor(p.x())), y0 = int(std::floor(p.y())), z0 = int(std::floor(p.z()));
  auto smooth = [](double t) { return float(t * t * (3.0 - 2.0 * t)); };
  const float tx = smooth(p.x() - x0), ty = smooth(p.y() - y0), tz = smooth(p.z() - z0);
  float v = 0.0f;
  for (int c = 0; c < 8; ++c) {
    const int dx = c & 1, dy = (c >> 1) & 1, dz = (c >> 2) & 1;
    const float w = (dx ? tx : 1 - tx) * (dy ? ty : 1 - ty) * (dz ? tz : 1 - tz);
    v += w * Hash(x0 + dx, y0 + dy, z0 + dz);
  }
  return v;
}

}  // namespace

Eigen::Vector3f EnvironmentColour(const Eigen::Vector3d& direction) {
  const Eigen::Vector3d d = direction.normalized();
  float noise = 0.0f, amplitude = 0.5f, total = 0.0f;
  for (int octave = 0; octave < 5; ++octave) {
    const double frequency = 6.0 * (1 << octave);
    noise += amplitude * ValueNoise(d * frequency + Eigen::Vector3d(17.0, 31.0, 47.0) * octave);
    total += amplitude;
    amplitude *= 0.6f;
  }
  noise /= total;
  // Light blue-grey above the horizon, dark brown below it; the noise varies both.
  const float up = float(std::clamp(d.z() * 4.0, -1.0, 1.0)) * 0.5f + 0.5f;
  const Eigen::Vector3f sky(0.55f, 0.65f, 0.8f), below(0.3f, 0.25f, 0.2f);
  const Eigen::Vector3f base = below + up * (sky - below);
  return (base * (0.45f + 1.1f * noise)).cwiseMin(1.0f).cwiseMax(0.0f);
}

}  // namespace vkr
