#include "pipelines/rendering/Environment.h"

#include <algorithm>
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
  // Two noise fields: one for brightness, one for hue, each with detail from a few degrees
  // up to a radian, and contrast like a cluttered real background's.
  auto field = [&](double offset) {
    float noise = 0.0f, amplitude = 0.5f, total = 0.0f;
    for (int octave = 0; octave < 5; ++octave) {
      const double frequency = 8.0 * (1 << octave);
      noise += amplitude * ValueNoise(d * frequency + Eigen::Vector3d(17.0, 31.0, 47.0) * (octave + offset));
      total += amplitude;
      amplitude *= 0.7f;
    }
    return std::clamp((noise / total - 0.5f) * 3.0f + 0.5f, 0.0f, 1.0f);  // stretched to [0,1]
  };
  const float brightness = field(0.0), hue = field(100.0);
  const Eigen::Vector3f warm(0.75f, 0.55f, 0.35f), cool(0.35f, 0.5f, 0.75f);
  const Eigen::Vector3f tint = warm + hue * (cool - warm);
  return (tint * (0.15f + 0.85f * brightness)).cwiseMin(1.0f).cwiseMax(0.0f);
}

}  // namespace vkr
