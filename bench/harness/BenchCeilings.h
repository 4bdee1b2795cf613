#pragma once
// The device's own ceilings, measured by `vkrecon bench` in the same run as the likelihood
// rows, so each pass can be reported as a share of what the device can do at all
// (LAVAPIPE.md lists the figures measured by hand on the CPU device).

#include <cstdint>

#include "engine/vk/Device.h"

namespace vkr {

struct CeilingOptions {
  // Bytes of the source buffer of the compute copy (a second buffer of the same size
  // receives it). Capped at 128 MiB, the largest storage buffer a shader may bind on lavapipe.
  uint64_t copy_bytes = 128ull << 20;
  // Side of the square RGBA16F target of the fill, and how many full-target draws one
  // timed repetition makes.
  uint32_t fill_side = 2048;
  int fill_draws = 16;
  int repeats = 5;  // timed repetitions after one warm-up; the median is reported
};

struct Ceilings {
  // Compute-shader copy, bytes read + bytes written per second.
  double copy_bytes_per_s = 0.0;
  uint64_t copy_bytes = 0;  // size of the buffer copied
  // Constant-colour fill of a whole RGBA16F target, fragments per second. Every draw is its
  // own rendering separated by a barrier, since llvmpipe drops opaque draws that a later
  // draw of the same binned scene covers (LAVAPIPE.md).
  double fill_fragments_per_s = 0.0;
  uint32_t fill_side = 0;
  int fill_draws = 0;
  // Not a ceiling of the device but a probe of the composite pass: its reduction (columns
  // per invocation, then a subgroup sum; shaders_glsl/bench_reduce.comp) alone over
  // fill_side² texels, texels per second.
  double reduction_texels_per_s = 0.0;
};

// Times both on `device` with GPU timestamps (medians over the repeats). `vkrecon bench`
// measures them at the start and again after the rows, and keeps the better of the two.
Ceilings MeasureCeilings(vk::Device& device, const CeilingOptions& options = {});

}  // namespace vkr
