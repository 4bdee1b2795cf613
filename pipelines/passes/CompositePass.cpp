#include "pipelines/passes/CompositePass.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <stdexcept>
#include <string>

#include "engine/vk/Check.h"
#include "engine/vk/Commands.h"
#include "pipelines/passes/PipelineBuilder.h"
#include "shaders/composite_comp.h"

namespace vkr {
namespace {

// Mirrors the push constants of shaders_glsl/composite.comp.
struct CompositePush {
  uint32_t size, partial_offset;
  float sigma2, delta2, outlier;
  uint32_t tile_offset;
};

constexpr uint32_t kCompositeRows = 16;  // composite.comp's texels per invocation (a column)

VkDescriptorSetLayoutBinding Binding(uint32_t b, VkDescriptorType type) {
  return {b, type, 1, VK_SHADER_STAGE_COMPUTE_BIT, nullptr};
}

}  // namespace

// A chart's texels at level l lie within its level-0 rectangle scaled by 2^−l; a texel of
// margin covers the rasteriser's rounding at the edges.
std::vector<uint32_t> CompositePass::ChartTiles(const AtlasLayout& layout, int level, uint32_t lanes) {
  const uint32_t size = uint32_t(layout.size) >> level;
  const uint32_t columns = (size + lanes - 1) / lanes, rows = (size + kCompositeRows - 1) / kCompositeRows;
  std::vector<char> used(size_t(columns) * rows, 0);
  const float scale = 1.0f / float(1 << level);
  for (const Chart& c : layout.charts) {
    const int x0 = std::max(0, int(std::floor(c.x * scale)) - 1), y0 = std::max(0, int(std::floor(c.y * scale)) - 1);
    const int x1 = std::min(int(size), int(std::ceil((c.x + c.w) * scale)) + 1);
    const int y1 = std::min(int(size), int(std::ceil((c.y + c.h) * scale)) + 1);
    for (int ty = y0 / int(kCompositeRows); ty * int(kCompositeRows) < y1; ++ty)
      for (int tx = x0 / int(lanes); tx * int(lanes) < x1; ++tx) used[size_t(ty) * columns + size_t(tx)] = 1;
  }
  std::vector<uint32_t> tiles;  // (x, y) pairs
  for (uint32_t ty = 0; ty < rows; ++ty)
    for (uint32_t tx = 0; tx < columns; ++tx)
      if (used[size_t(ty) * columns + tx]) tiles.insert(tiles.end(), {tx, ty});
  return tiles;
}

namespace {

std::vector<std::vector<uint32_t>> TilesPerLevel(const AtlasLayout& layout, int levels, uint32_t lanes) {
  std::vector<std::vector<uint32_t>> out;
  for (int l = 0; l < levels; ++l) out.push_back(CompositePass::ChartTiles(layout, l, lanes));
  return out;
}

uint32_t MostTiles(const std::vector<std::vector<uint32_t>>& tiles) {
  size_t most = 1;
  for (const auto& t : tiles) most = std::max(most, t.size() / 2);
  return uint32_t(most);
}

}  // namespace

CompositePass::CompositePass(vk::Device& device, const std::vector<Inputs>& inputs, const AtlasLayout& layout,
                             int levels, int max_batch)
    : CompositePass(device, inputs, TilesPerLevel(layout, levels, device.subgroup_size()), max_batch) {}

CompositePass::CompositePass(vk::Device& device, const std::vector<Inputs>& inputs,
                             const std::vector<std::vector<uint32_t>>& tiles, int max_batch)
    : view_count_(inputs.at(0).views->info().layers),
      lanes_(device.subgroup_size()),
      atlas_size_(inputs.at(0).views->info().width),
      reduce_(device, max_batch, MostTiles(tiles)),
      photometric_(device, VkDeviceSize(view_count_) * 8 * sizeof(float), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT,
                   vk::MemoryUse::Upload) {
  for (const Inputs& in : inputs)
    if (in.views->info().layers != view_count_ || in.views->info().width != atlas_size_)
      throw std::invalid_argument("CompositePass: input sets of different view counts or sizes");
  size_t all = 0;
  for (const auto& t : tiles) all += t.size();
  tiles_ = vk::Buffer(device, VkDeviceSize(std::max<size_t>(all, 2)) * sizeof(uint32_t),
                      VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, vk::MemoryUse::Upload);
  uint32_t offset = 0;
  for (const auto& t : tiles) {
    if (!t.empty()) std::memcpy(tiles_.data<uint32_t>() + offset, t.data(), t.size() * sizeof(uint32_t));
    tile_offset_.push_back(offset / 2);
    tile_count_.push_back(uint32_t(t.size() / 2));
    offset += uint32_t(t.size());
  }
  const uint32_t size = atlas_size_;
  const VkImageUsageFlags dump_usage =
      VK_IMAGE_USAGE_STORAGE_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT;
  composite_ = vk::GpuImage(device, {size, size, 1, VK_FORMAT_R32G32B32A32_SFLOAT, dump_usage});
  deviation_ = vk::GpuImage(device, {size, size, 1, VK_FORMAT_R32G32B32A32_SFLOAT, dump_usage});
  noise_ = vk::GpuImage(device, {size, size, 1, VK_FORMAT_R32G32B32A32_SFLOAT, dump_usage});
  SetPhotometric(PhotometricCorrection::Identity(int(view_count_)));

  const std::vector<VkDescriptorSetLayoutBinding> composite_bindings = {
      Binding(0, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE), Binding(1, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE),
      Binding(2, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER), Binding(3, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE),
      Binding(4, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE), Binding(5, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER),
      Binding(6, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE), Binding(7, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER)};
  composite_set_layout_ = CreateDescriptorSetLayout(device, composite_bindings);
  composite_layout_ = CreatePipelineLayout(device, composite_set_layout_, sizeof(CompositePush),
                                           VK_SHADER_STAGE_COMPUTE_BIT);
  DescriptorSets cs = AllocateDescriptorSets(device, composite_set_layout_, composite_bindings, uint32_t(inputs.size()));
  composite_pool_ = std::move(cs.pool);
  composite_sets_ = std::move(cs.sets);
  for (size_t k = 0; k < inputs.size(); ++k) {
    const VkDescriptorSet set = composite_sets_[k];
    WriteStorageImage(device, set, 0, inputs[k].views->view());
    WriteStorageImage(device, set, 1, inputs[k].mask->view());
    WriteStorageBuffer(device, set, 2, reduce_.partials());
    WriteStorageImage(device, set, 3, composite_.view());
    WriteStorageImage(device, set, 4, deviation_.view());
    WriteStorageBuffer(device, set, 5, photometric_);
    WriteStorageImage(device, set, 6, noise_.view());
    WriteStorageBuffer(device, set, 7, tiles_);
  }

  const vk::ShaderModule composite = vk::CreateShaderModule(device, kCompositeComp, sizeof(kCompositeComp));
  composite_pipeline_ = CreateSubgroupComputePipeline(device, composite, composite_layout_, {view_count_, 0u});
  dump_pipeline_ = CreateSubgroupComputePipeline(device, composite, composite_layout_, {view_count_, 1u});

  // The dump images live in GENERAL for the whole run.
  vk::CommandContext context(device);
  VkCommandBuffer cmd = context.Begin();
  for (const vk::GpuImage* image : {&composite_, &deviation_, &noise_})
    vk::ImageBarrier(cmd, *image, VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_GENERAL,
                     VK_PIPELINE_STAGE_2_NONE, 0, VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT,
                     VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT);
  context.SubmitAndWait();
}

int CompositePass::Level(uint32_t level_size) const {
  for (size_t l = 0; l < tile_count_.size(); ++l)
    if ((atlas_size_ >> l) == level_size) return int(l);
  throw std::invalid_argument("CompositePass: no level of atlas side " + std::to_string(level_size));
}

uint64_t CompositePass::TexelsVisited(uint32_t level_size) const {
  return uint64_t(tile_count_[size_t(Level(level_size))]) * lanes_ * kCompositeRows;
}

void CompositePass::SetPhotometric(const PhotometricCorrection& correction) {
  if (correction.cameras() != int(view_count_))
    throw std::invalid_argument("CompositePass::SetPhotometric: a correction for " +
                                std::to_string(correction.cameras()) + " cameras, not " + std::to_string(view_count_));
  float* out = photometric_.data<float>();
  for (uint32_t i = 0; i < view_count_; ++i) {
    const auto& g = correction.gain[i];
    const auto& o = correction.offset[i];
    const float values[8] = {float(g[0]), float(g[1]), float(g[2]), float((g[0] + g[1] + g[2]) / 3.0),
                             float(o[0]), float(o[1]), float(o[2]), 0.0f};
    std::memcpy(out + 8 * i, values, sizeof values);
  }
}

void CompositePass::record(VkCommandBuffer cmd, int slot, int inputs, uint32_t level_size,
                           const LikelihoodModel& model, bool write_images) const {
  const double sigma = model.sigma / 255.0;
  const CompositePush push{level_size,
                           uint32_t(slot) * reduce_.partial_stride(),
                           float(sigma * sigma),
                           float(model.position_sd * model.position_sd),
                           float(model.outlier_chi2),
                           tile_offset_[size_t(Level(level_size))]};
  vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, write_images ? dump_pipeline_ : composite_pipeline_);
  vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, composite_layout_, 0, 1,
                          &composite_sets_.at(size_t(inputs)), 0, nullptr);
  vkCmdPushConstants(cmd, composite_layout_, VK_SHADER_STAGE_COMPUTE_BIT, 0, sizeof(push), &push);
  const uint32_t tiles = tile_count_[size_t(Level(level_size))];
  if (write_images) {  // texels off the charts are not visited: let them read 0 in the dumps
    vk::MemoryBarrier(cmd, VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT, VK_ACCESS_2_MEMORY_READ_BIT | VK_ACCESS_2_MEMORY_WRITE_BIT,
                      VK_PIPELINE_STAGE_2_CLEAR_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT);
    const VkClearColorValue zero{};
    const VkImageSubresourceRange all{VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 1};
    for (const vk::GpuImage* image : {&composite_, &deviation_, &noise_})
      vkCmdClearColorImage(cmd, image->handle(), VK_IMAGE_LAYOUT_GENERAL, &zero, 1, &all);
    vk::MemoryBarrier(cmd, VK_PIPELINE_STAGE_2_CLEAR_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT,
                      VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT, VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT);
  }
  if (tiles > 0) vkCmdDispatch(cmd, tiles, 1, 1);
}

void CompositePass::record_reduce(VkCommandBuffer cmd, int batch, uint32_t level_size) const {
  reduce_.record(cmd, batch, tile_count_[size_t(Level(level_size))]);
}

ReducedScalars CompositePass::Result(int slot) const { return reduce_.Result(slot); }

}  // namespace vkr
