#include "pipelines/likelihood/MemoryPlan.h"

#include <algorithm>
#include <cstdio>
#include <fstream>

#include "engine/common/InputError.h"
#include "engine/scene/Scene.h"
#include "engine/vk/Device.h"
#include "pipelines/likelihood/ImageLikelihood.h"
#include "pipelines/likelihood/SurfaceLikelihood.h"

namespace vkr {
namespace {

constexpr uint64_t kScalarsBytes = 48;     // GpuScalars (ReducePass.cpp, scalars.glsl)
constexpr uint64_t kRowsPerInvocation = 16;  // composite.comp and image_compare.comp sum columns of 16
constexpr uint64_t kHostPixelBytes = 16;   // a host Image pixel: 4 floats
// A CPU device (lavapipe) keeps more host memory resident than the device memory it hands
// out: `vkrecon likelihood` on the box asset (9 cameras, 640×480) peaked at 0.66, 2.25 and
// 8.6 GB resident with atlases of 1024, 2048 and 4096, 4.2–4.4× the plan's device total
// (Mesa 22.3). The plan is checked against the host's available memory with that factor.
constexpr double kCpuResidentPerDeviceByte = 4.4;

uint64_t CeilDiv(uint64_t a, uint64_t b) { return (a + b - 1) / b; }

// The mips of a w × h image down to a smallest side of 4 (ReferenceMipCount), in pixels:
// a full chain is at most 4/3 of level 0.
uint64_t MipChainPixels(uint64_t w, uint64_t h) {
  uint64_t pixels = 0;
  for (int m = 0;; ++m) {
    pixels += std::max<uint64_t>(1, w >> m) * std::max<uint64_t>(1, h >> m);
    if ((std::min(w, h) >> (m + 1)) < 4) break;
  }
  return pixels;
}

std::string Times(uint64_t a, uint64_t b) { return std::to_string(a) + " × " + std::to_string(b); }

// What every likelihood keeps per camera: the photograph with its mips (RGBA8), the validity
// (R8, when the camera has a mask or a lens), one depth map (D32F) per level; and the staging
// buffer, which keeps the largest upload. The host peak is one photograph's float pyramid.
void PlanCameras(const Scene& scene, int levels, MemoryPlan* plan, int depth_copies = 1) {
  uint64_t largest_mips = 0, largest_photo = 0;
  for (const CameraModel& c : scene.cameras) {
    const uint64_t w = uint64_t(std::max(1, c.width)), h = uint64_t(std::max(1, c.height));
    const uint64_t mips = MipChainPixels(w, h);
    plan->device.push_back({c.name + " photograph " + Times(w, h) + " RGBA8 with mips", mips * 4});
    if (!c.mask.empty() || !c.distortion.IsNone())
      plan->device.push_back({c.name + " validity " + Times(w, h) + " R8 with mips", mips});
    for (int l = 0; l < levels; ++l)
      plan->device.push_back({c.name + " depth level " + std::to_string(l) +
                                  (depth_copies > 1 ? " × " + std::to_string(depth_copies) + " slots" : ""),
                              CeilDiv(w, uint64_t(1) << l) * CeilDiv(h, uint64_t(1) << l) * 4 * uint64_t(depth_copies),
                              depth_copies > 1});
    largest_mips = std::max(largest_mips, mips);
    largest_photo = std::max(largest_photo, w * h);
  }
  plan->device.push_back({"upload staging (the largest photograph's mips)", largest_mips * 4});
  plan->host = std::max(plan->host, largest_photo * kHostPixelBytes * 3);  // photo, undistorted copy, pyramid
}

// Per hypothesis: the node matrices (and the interior pass's inverses and candidates).
void PlanNodes(const Scene& scene, int max_batch, bool interior, MemoryPlan* plan) {
  const uint64_t k = uint64_t(max_batch), nodes = std::max<uint64_t>(1, scene.nodes.size());
  plan->device.push_back({"node matrices " + Times(k, nodes) + " × 64 B", k * nodes * 64, true});
  if (!interior) return;
  plan->device.push_back({"interior inverses " + Times(k, nodes) + " × 64 B", k * nodes * 64, true});
  plan->device.push_back({"interior candidates " + Times(k, nodes) + " × 32 B", k * nodes * 32, true});
}

}  // namespace

uint64_t MemoryPlan::device_total() const {
  uint64_t total = 0;
  for (const MemoryItem& item : device) total += item.bytes;
  return total;
}

uint64_t MemoryPlan::per_hypothesis_total() const {
  uint64_t total = 0;
  for (const MemoryItem& item : device)
    if (item.per_hypothesis) total += item.bytes;
  return total;
}

const MemoryItem* MemoryPlan::largest() const {
  const MemoryItem* best = nullptr;
  for (const MemoryItem& item : device)
    if (!best || item.bytes > best->bytes) best = &item;
  return best;
}

MemoryLimits MemoryLimits::Of(const vk::Device& device) {
  MemoryLimits limits;
  limits.device_name = device.name();
  limits.heap = device.device_local_heap_bytes();
  limits.max_allocation = device.max_allocation_bytes();
  limits.device_memory_is_host = device.is_cpu();
  std::ifstream meminfo("/proc/meminfo");
  std::string key;
  uint64_t kib = 0;
  std::string unit;
  while (meminfo >> key >> kib >> unit)
    if (key == "MemAvailable:") limits.host_available = kib * 1024;
  return limits;
}

MemoryPlan PlanSurfaceLikelihood(const Scene& scene, const SurfaceLikelihoodOptions& options, uint32_t subgroup_size) {
  MemoryPlan plan;
  // Per-slot images (SlotImages): the depth maps, view layers and mask once per hypothesis.
  const bool per_slot = options.slot_images == SlotImages::PerSlot;
  const uint64_t copies = per_slot ? uint64_t(options.max_batch) : 1;
  const std::string times = per_slot ? " × " + std::to_string(copies) + " slots" : "";
  PlanCameras(scene, options.levels, &plan, int(copies));
  const uint64_t atlas = uint64_t(options.atlas), texels = atlas * atlas, n = scene.cameras.size();
  const std::string side = std::to_string(atlas) + "²";
  plan.device.push_back({"view textures " + std::to_string(n) + " × " + side + " × 8 B" + times, copies * n * texels * 8, per_slot});
  plan.device.push_back({"interior mask " + side + " × 4 B" + times, copies * texels * 4, per_slot});
  for (const char* image : {"composite", "deviation", "noise"})  // written by dumps, allocated always
    plan.device.push_back({std::string(image) + " image " + side + " × 16 B", texels * 16});
  const uint64_t groups = CeilDiv(atlas, std::max<uint32_t>(1, subgroup_size)) * CeilDiv(atlas, kRowsPerInvocation);
  const uint64_t k = uint64_t(options.max_batch);
  plan.device.push_back({"composite partial sums " + Times(k, groups) + " × 48 B", k * groups * kScalarsBytes, true});
  PlanNodes(scene, options.max_batch, true, &plan);
  plan.host += n * texels / 8;  // the interior pass's and the atlas's host tables, about a bit per texel per view
  return plan;
}

MemoryPlan PlanImageLikelihood(const Scene& scene, const ImageLikelihoodOptions& options, uint32_t subgroup_size) {
  MemoryPlan plan;
  PlanCameras(scene, options.levels, &plan);
  const uint64_t n = scene.cameras.size();
  const uint64_t partners = options.partners <= 0 || uint64_t(options.partners) >= n - 1 ? n - 1 : uint64_t(options.partners);
  const uint64_t pairs = n * partners;
  uint64_t w = 1, h = 1;
  for (const CameraModel& c : scene.cameras) {
    w = std::max<uint64_t>(w, uint64_t(c.width));
    h = std::max<uint64_t>(h, uint64_t(c.height));
  }
  plan.device.push_back({"pair results " + std::to_string(pairs) + " × " + Times(w, h) + " × 4 B", pairs * w * h * 4});
  const uint64_t k = uint64_t(options.max_batch);
  const uint64_t groups = CeilDiv(w, std::max<uint32_t>(1, subgroup_size)) * CeilDiv(h, kRowsPerInvocation);
  plan.device.push_back({"compare partial sums " + Times(k, groups) + " × 48 B", k * groups * kScalarsBytes, true});
  PlanNodes(scene, options.max_batch, false, &plan);
  return plan;
}

std::string WhyItDoesNotFit(const MemoryPlan& plan, const MemoryLimits& limits) {
  const uint64_t total = plan.device_total();
  const MemoryItem* largest = plan.largest();
  const bool one_too_large = largest && limits.max_allocation > 0 && largest->bytes > limits.max_allocation;
  const std::string needs = "it needs " + FormatBytes(total) + " of device memory" +
                            (largest ? " (the largest part " + largest->what + " = " + FormatBytes(largest->bytes) + ")" : "");
  const std::string device = "the device (" + limits.device_name + ")";
  if (one_too_large || (limits.heap > 0 && total > limits.heap))
    return needs + " but " + device + " has " + FormatBytes(limits.heap) +
           (limits.max_allocation > 0 ? ", at most " + FormatBytes(limits.max_allocation) + " in one allocation" : "");
  const uint64_t resident = uint64_t(kCpuResidentPerDeviceByte * double(total)) + plan.host;
  if (limits.device_memory_is_host && limits.host_available > 0 && resident > limits.host_available)
    return needs + ", which on " + device + " keeps about " + FormatBytes(resident) +
           " of host memory resident, but " + FormatBytes(limits.host_available) + " is available";
  return {};
}

void RequireSurfaceLikelihoodFits(const Scene& scene, const SurfaceLikelihoodOptions& options,
                                  const vk::Device& device) {
  RequireSurfaceLikelihoodFits(scene, options, MemoryLimits::Of(device), device.subgroup_size());
}

void RequireSurfaceLikelihoodFits(const Scene& scene, const SurfaceLikelihoodOptions& options,
                                  const MemoryLimits& limits, uint32_t subgroup_size) {
  const std::string why = WhyItDoesNotFit(PlanSurfaceLikelihood(scene, options, subgroup_size), limits);
  if (why.empty()) return;
  // What to change: the batch when its buffers are most of the plan, else the atlas; halved
  // until the plan fits.
  const MemoryPlan plan = PlanSurfaceLikelihood(scene, options, subgroup_size);
  const bool batch = plan.per_hypothesis_total() * 2 > plan.device_total();
  SurfaceLikelihoodOptions smaller = options;
  int& value = batch ? smaller.max_batch : smaller.atlas;
  const int lowest = batch ? 1 : 16;
  auto fits = [&] {
    if (!batch)
      while (smaller.levels > 1 && (smaller.atlas >> (smaller.levels - 1)) < 16) --smaller.levels;
    return WhyItDoesNotFit(PlanSurfaceLikelihood(scene, smaller, subgroup_size), limits).empty();
  };
  while (value > lowest && !fits()) value /= 2;
  const std::string fix =
      fits() ? "; " + std::string(batch ? "a batch of " : "an atlas of ") + std::to_string(value) + " would fit (" +
                   FormatBytes(PlanSurfaceLikelihood(scene, smaller, subgroup_size).device_total()) + ")"
             : "; nothing smaller fits either: use smaller photographs or fewer cameras";
  throw InputError(scene.file.string(), batch ? "sampler.batch" : "likelihood.atlas",
                   std::to_string(batch ? options.max_batch : options.atlas) + " with " +
                       std::to_string(scene.cameras.size()) + " cameras does not fit: " + why + fix);
}

void RequireImageLikelihoodFits(const Scene& scene, const ImageLikelihoodOptions& options, const vk::Device& device) {
  const MemoryLimits limits = MemoryLimits::Of(device);
  const std::string why = WhyItDoesNotFit(PlanImageLikelihood(scene, options, device.subgroup_size()), limits);
  if (why.empty()) return;
  throw InputError(scene.file.string(), "likelihood.kind",
                   "the image-space likelihood over " + std::to_string(scene.cameras.size()) +
                       " cameras does not fit: " + why +
                       "; use the surface likelihood, smaller photographs or fewer cameras");
}

std::string FormatBytes(uint64_t bytes) {
  const char* units[] = {"B", "KiB", "MiB", "GiB", "TiB"};
  double value = double(bytes);
  int unit = 0;
  while (value >= 1024.0 && unit < 4) {
    value /= 1024.0;
    ++unit;
  }
  char text[32];
  std::snprintf(text, sizeof text, unit == 0 ? "%.0f %s" : value < 10 ? "%.1f %s" : "%.0f %s", value, units[unit]);
  return text;
}

}  // namespace vkr
