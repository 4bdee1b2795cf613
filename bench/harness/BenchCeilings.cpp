#include "bench/harness/BenchCeilings.h"

#include <algorithm>
#include <vector>

#include "engine/vk/Commands.h"
#include "engine/vk/Resources.h"
#include "pipelines/passes/PipelineBuilder.h"
#include "shaders/bench_copy_comp.h"
#include "shaders/bench_fill_frag.h"
#include "shaders/bench_fill_vert.h"
#include "shaders/bench_reduce_comp.h"

namespace vkr {
namespace {

double MedianSeconds(std::vector<double> v) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  const size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

// The start timestamp + the barrier without which it may be taken before the work it precedes.
void StartTimer(VkCommandBuffer cmd, vk::TimestampQueries& timestamps) {
  timestamps.Reset(cmd);
  timestamps.Write(cmd, 0);
  vk::MemoryBarrier(cmd, VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT, 0, VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT, 0);
}

void StopTimer(VkCommandBuffer cmd, vk::TimestampQueries& timestamps) {
  vk::MemoryBarrier(cmd, VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT, 0, VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT, 0);
  timestamps.Write(cmd, 1);
}

// One warm-up (JIT compilation) and `repeats` timed submissions of `record`: median seconds.
template <class Record>
double TimeSubmissions(vk::Device& device, int repeats, const Record& record) {
  vk::CommandContext context(device);
  vk::TimestampQueries timestamps(device, 2);
  std::vector<double> seconds;
  for (int r = 0; r <= repeats; ++r) {
    VkCommandBuffer cmd = context.Begin();
    StartTimer(cmd, timestamps);
    record(cmd);
    StopTimer(cmd, timestamps);
    context.SubmitAndWait();
    if (r > 0) seconds.push_back(timestamps.ReadMs(2)[1] * 1e-3);
  }
  return MedianSeconds(seconds);
}

double MeasureCopy(vk::Device& device, uint64_t bytes, int repeats) {
  const VkBufferUsageFlags usage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT;
  vk::Buffer source(device, bytes, usage, vk::MemoryUse::Device);
  vk::Buffer destination(device, bytes, usage, vk::MemoryUse::Device);
  const std::vector<VkDescriptorSetLayoutBinding> bindings = {
      {0, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 1, VK_SHADER_STAGE_COMPUTE_BIT, nullptr},
      {1, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 1, VK_SHADER_STAGE_COMPUTE_BIT, nullptr}};
  const vk::DescriptorSetLayout set_layout = CreateDescriptorSetLayout(device, bindings);
  const vk::PipelineLayout layout = CreatePipelineLayout(device, set_layout, sizeof(uint32_t), VK_SHADER_STAGE_COMPUTE_BIT);
  DescriptorSets sets = AllocateDescriptorSets(device, set_layout, bindings);
  WriteStorageBuffer(device, sets.sets[0], 0, source);
  WriteStorageBuffer(device, sets.sets[0], 1, destination);
  const vk::ShaderModule shader = vk::CreateShaderModule(device, kBenchCopyComp, sizeof(kBenchCopyComp));
  const vk::Pipeline pipeline = CreateComputePipeline(device, shader, layout);

  const uint32_t count = uint32_t(bytes / 16);  // uvec4 elements
  const uint32_t groups = std::min<uint32_t>((count + 255) / 256, device.properties().limits.maxComputeWorkGroupCount[0]);
  const double seconds = TimeSubmissions(device, repeats, [&](VkCommandBuffer cmd) {
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, pipeline);
    vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, layout, 0, 1, &sets.sets[0], 0, nullptr);
    vkCmdPushConstants(cmd, layout, VK_SHADER_STAGE_COMPUTE_BIT, 0, sizeof(count), &count);
    vkCmdDispatch(cmd, groups, 1, 1);
  });
  return seconds > 0 ? 2.0 * double(count) * 16.0 / seconds : 0.0;
}

double MeasureFill(vk::Device& device, uint32_t side, int draws, int repeats) {
  constexpr VkFormat kFormat = VK_FORMAT_R16G16B16A16_SFLOAT;  // the view textures' format
  vk::GpuImage target(device, {side, side, 1, kFormat, VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT});
  const vk::PipelineLayout layout = CreatePipelineLayout(device, VK_NULL_HANDLE, 4 * sizeof(float), VK_SHADER_STAGE_FRAGMENT_BIT);
  const vk::ShaderModule vert = vk::CreateShaderModule(device, kBenchFillVert, sizeof(kBenchFillVert));
  const vk::ShaderModule frag = vk::CreateShaderModule(device, kBenchFillFrag, sizeof(kBenchFillFrag));
  GraphicsPipelineDesc desc;
  desc.vertex = vert;
  desc.fragment = frag;
  desc.layout = layout;
  desc.colour_formats = {kFormat};
  desc.depth_write = false;
  desc.vertex_attributes = 0;  // the triangle comes from gl_VertexIndex
  const vk::Pipeline pipeline = CreateGraphicsPipeline(device, desc);
  // The pipeline declares the scene's vertex binding (PipelineBuilder.h) though the shader
  // reads no attribute; validation still wants a buffer bound to it.
  const vk::Buffer unused_vertices(device, sizeof(float) * 16, VK_BUFFER_USAGE_VERTEX_BUFFER_BIT, vk::MemoryUse::Device);

  const double seconds = TimeSubmissions(device, repeats, [&](VkCommandBuffer cmd) {
    vk::ImageBarrier(cmd, target, VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL,
                     VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT, VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT,
                     VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT, VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT);
    for (int d = 0; d < draws; ++d) {
      VkRenderingAttachmentInfo colour{VK_STRUCTURE_TYPE_RENDERING_ATTACHMENT_INFO};
      colour.imageView = target.view();
      colour.imageLayout = VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL;
      colour.loadOp = VK_ATTACHMENT_LOAD_OP_LOAD;
      colour.storeOp = VK_ATTACHMENT_STORE_OP_STORE;
      VkRenderingInfo info{VK_STRUCTURE_TYPE_RENDERING_INFO};
      info.renderArea = {{0, 0}, {side, side}};
      info.layerCount = 1;
      info.colorAttachmentCount = 1;
      info.pColorAttachments = &colour;
      vkCmdBeginRendering(cmd, &info);
      SetViewport(cmd, side, side);
      vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, pipeline);
      const VkBuffer vertex_buffer = unused_vertices.handle();
      const VkDeviceSize offset = 0;
      vkCmdBindVertexBuffers(cmd, 0, 1, &vertex_buffer, &offset);
      const float value = float(d + 1) / float(draws + 1);
      const float rgba[4] = {value, 1.0f - value, 0.5f, 1.0f};
      vkCmdPushConstants(cmd, layout, VK_SHADER_STAGE_FRAGMENT_BIT, 0, sizeof(rgba), rgba);
      vkCmdDraw(cmd, 3, 1, 0, 0);
      vkCmdEndRendering(cmd);
      // Each draw is finished before the next begins: nothing can be dropped as covered.
      vk::MemoryBarrier(cmd, VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT, VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT,
                        VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT,
                        VK_ACCESS_2_COLOR_ATTACHMENT_READ_BIT | VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT);
    }
  });
  return seconds > 0 ? double(side) * side * draws / seconds : 0.0;
}

double MeasureReduction(vk::Device& device, uint32_t side, int repeats) {
  constexpr uint32_t kRows = 16;  // bench_reduce.comp's texels per invocation
  const uint32_t groups_x = (side + device.subgroup_size() - 1) / device.subgroup_size();
  const uint32_t groups_y = (side + kRows - 1) / kRows;
  constexpr VkDeviceSize kScalarsBytes = 48;  // struct Scalars of scalars.glsl
  vk::Buffer partials(device, VkDeviceSize(groups_x) * groups_y * kScalarsBytes, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT,
                      vk::MemoryUse::Device);
  const std::vector<VkDescriptorSetLayoutBinding> bindings = {
      {0, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 1, VK_SHADER_STAGE_COMPUTE_BIT, nullptr}};
  const vk::DescriptorSetLayout set_layout = CreateDescriptorSetLayout(device, bindings);
  const vk::PipelineLayout layout = CreatePipelineLayout(device, set_layout, 0, 0);
  DescriptorSets sets = AllocateDescriptorSets(device, set_layout, bindings);
  WriteStorageBuffer(device, sets.sets[0], 0, partials);
  const vk::ShaderModule shader = vk::CreateShaderModule(device, kBenchReduceComp, sizeof(kBenchReduceComp));
  const vk::Pipeline pipeline = CreateSubgroupComputePipeline(device, shader, layout);
  const double seconds = TimeSubmissions(device, repeats, [&](VkCommandBuffer cmd) {
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, pipeline);
    vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, layout, 0, 1, &sets.sets[0], 0, nullptr);
    vkCmdDispatch(cmd, groups_x, groups_y, 1);
  });
  return seconds > 0 ? double(side) * side / seconds : 0.0;
}

}  // namespace

Ceilings MeasureCeilings(vk::Device& device, const CeilingOptions& options) {
  Ceilings c;
  const uint64_t limit = device.properties().limits.maxStorageBufferRange;
  c.copy_bytes = std::max<uint64_t>(16, std::min(options.copy_bytes, limit) / 16 * 16);
  c.copy_bytes_per_s = MeasureCopy(device, c.copy_bytes, options.repeats);
  c.fill_side = options.fill_side;
  c.fill_draws = options.fill_draws;
  c.fill_fragments_per_s = MeasureFill(device, options.fill_side, options.fill_draws, options.repeats);
  c.reduction_texels_per_s = MeasureReduction(device, options.fill_side, options.repeats);
  return c;
}

}  // namespace vkr
