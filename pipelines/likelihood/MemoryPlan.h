#pragma once
// What a likelihood will allocate, worked out from the scene and the settings before
// anything is allocated. Settings that cannot fit then end with exit 2 and the numbers
// (what needs how much, what the device has, what would fit) instead of a raw
// VK_ERROR_OUT_OF_DEVICE_MEMORY from a pass deep inside, or a run that pages for minutes.
// The plan follows the constructors' allocations; a test holds it to what they allocate.

#include <cstdint>
#include <string>
#include <vector>

namespace vkr {

class Scene;
struct SurfaceLikelihoodOptions;
struct ImageLikelihoodOptions;
namespace vk {
class Device;
}

struct MemoryItem {
  std::string what;    // e.g. "view textures 9 × 8192² × 8 B"
  uint64_t bytes = 0;  // one allocation
  bool per_hypothesis = false;  // grows with the batch (sampler.batch), not with the atlas
};

struct MemoryPlan {
  std::vector<MemoryItem> device;  // each item one allocation
  uint64_t host = 0;               // host memory at the peak of creation, beyond the device's

  uint64_t device_total() const;
  uint64_t per_hypothesis_total() const;
  const MemoryItem* largest() const;  // null when empty
};

// What the plan is checked against.
struct MemoryLimits {
  std::string device_name;
  uint64_t heap = 0;            // the largest device-local heap
  uint64_t max_allocation = 0;  // maxMemoryAllocationSize (0: unknown)
  // On a CPU device (lavapipe) device memory is host memory: the plan's device and host
  // bytes together must fit in what the host has available.
  bool device_memory_is_host = false;
  uint64_t host_available = 0;  // MemAvailable (0: unknown)

  static MemoryLimits Of(const vk::Device& device);
};

MemoryPlan PlanSurfaceLikelihood(const Scene& scene, const SurfaceLikelihoodOptions& options,
                                 uint32_t subgroup_size);
MemoryPlan PlanImageLikelihood(const Scene& scene, const ImageLikelihoodOptions& options,
                               uint32_t subgroup_size);

// Why the plan does not fit within the limits, in one clause naming the numbers; empty when
// it fits.
std::string WhyItDoesNotFit(const MemoryPlan& plan, const MemoryLimits& limits);

// Throws InputError (exit 2) naming the scene file and the setting to change when the
// likelihood the options describe cannot fit, with the largest atlas (or batch) that would.
void RequireSurfaceLikelihoodFits(const Scene& scene, const SurfaceLikelihoodOptions& options,
                                  const vk::Device& device);
void RequireSurfaceLikelihoodFits(const Scene& scene, const SurfaceLikelihoodOptions& options,
                                  const MemoryLimits& limits, uint32_t subgroup_size);
void RequireImageLikelihoodFits(const Scene& scene, const ImageLikelihoodOptions& options,
                                const vk::Device& device);

// "4.5 GiB", "768 MiB", "12 KiB".
std::string FormatBytes(uint64_t bytes);

}  // namespace vkr
