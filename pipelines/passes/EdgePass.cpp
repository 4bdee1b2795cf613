#include "pipelines/passes/EdgePass.h"

#include <Eigen/Geometry>
#include <cmath>
#include <cstring>
#include <map>
#include <tuple>

#include "engine/vk/Commands.h"
#include "pipelines/passes/PipelineBuilder.h"
#include "pipelines/passes/Projection.h"
#include "shaders/edges_comp.h"

namespace vkr {
namespace {

// Mirrors edges.comp's Edge (std430).
struct GpuEdge {
  float a[4], b[4], c0[4], c1[4];
};
static_assert(sizeof(GpuEdge) == 64);

// Mirrors edges.comp's push constants.
struct EdgePush {
  float clip_from_world[16];
  float centre[4];
  float image[4];
  float statistic[4];
  uint32_t node_offset, edge_count, dump_camera, partial_offset;
};
static_assert(sizeof(EdgePush) == 128);

constexpr double kPi = 3.14159265358979323846;

// One triangle's side, as FindModelEdges collects them per welded edge.
struct Side {
  Eigen::Vector3f opposite, normal;  // the triangle's third vertex and its outward normal
};

}  // namespace

std::vector<ModelEdge> FindModelEdges(const SceneGeometry& geometry) {
  // Weld by exact position within a node: the primitives give a face's corners the very
  // coordinates its neighbours give theirs.
  std::map<std::tuple<uint32_t, float, float, float>, uint32_t> welded;
  std::vector<uint32_t> weld(geometry.vertices.size());
  for (size_t v = 0; v < geometry.vertices.size(); ++v) {
    const GpuVertex& g = geometry.vertices[v];
    const auto key = std::make_tuple(g.node, g.position[0], g.position[1], g.position[2]);
    weld[v] = welded.emplace(key, uint32_t(welded.size())).first->second;
  }
  auto position = [&](uint32_t v) {
    const float* p = geometry.vertices[v].position;
    return Eigen::Vector3f(p[0], p[1], p[2]);
  };
  // Per undirected welded edge: its endpoints (original vertex indices) and its sides.
  struct Collected {
    uint32_t a = 0, b = 0;
    std::vector<Side> sides;
  };
  std::map<std::pair<uint32_t, uint32_t>, Collected> collected;
  for (size_t t = 0; t + 2 < geometry.indices.size(); t += 3) {
    const uint32_t v[3] = {geometry.indices[t], geometry.indices[t + 1], geometry.indices[t + 2]};
    const Eigen::Vector3f normal = (position(v[1]) - position(v[0])).cross(position(v[2]) - position(v[0]));
    if (normal.norm() == 0.0f) continue;  // degenerate: no face to see
    for (int k = 0; k < 3; ++k) {
      const uint32_t u = v[k], w = v[(k + 1) % 3];
      if (weld[u] == weld[w]) continue;
      Collected& c = collected[{std::min(weld[u], weld[w]), std::max(weld[u], weld[w])}];
      if (c.sides.empty()) c.a = u, c.b = w;
      c.sides.push_back({position(v[(k + 2) % 3]), normal.normalized()});
    }
  }
  const float flat = float(std::cos(kPi / 180.0));
  std::vector<ModelEdge> edges;
  for (const auto& [key, c] : collected) {
    if (c.sides.size() > 2) continue;
    if (c.sides.size() == 2 && c.sides[0].normal.dot(c.sides[1].normal) > flat) continue;
    ModelEdge e;
    e.a = position(c.a);
    e.b = position(c.b);
    e.node = geometry.vertices[c.a].node;
    auto sign = [&](const Side& side) {
      return (e.b - e.a).cross(side.opposite - e.a).dot(side.normal) > 0.0f ? 1.0f : -1.0f;
    };
    e.c0 = c.sides[0].opposite;
    e.sign0 = sign(c.sides[0]);
    e.c1 = c.sides.size() == 2 ? c.sides[1].opposite : e.c0;
    e.sign1 = c.sides.size() == 2 ? sign(c.sides[1]) : 0.0f;
    edges.push_back(e);
  }
  return edges;
}

EdgePass::EdgePass(vk::Device& device, const GpuScene& scene, const std::vector<ModelEdge>& edges, int bindings,
                   int cameras, int max_batch, double depth_tolerance)
    : device_(&device),
      scene_(&scene),
      edge_count_(uint32_t(edges.size())),
      lanes_(device.subgroup_size()),
      cameras_(cameras),
      trilinear_(vk::CreateTrilinearClampSampler(device)),
      nearest_(vk::CreateNearestClampSampler(device)) {
  groups_ = std::max(1u, (edge_count_ + lanes_ - 1) / lanes_);
  edges_ = vk::Buffer(device, std::max<size_t>(1, edges.size()) * sizeof(GpuEdge), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT,
                      vk::MemoryUse::Upload);
  GpuEdge* out = edges_.data<GpuEdge>();
  for (const ModelEdge& e : edges) {
    GpuEdge g{};
    for (int k = 0; k < 3; ++k) g.a[k] = e.a[k], g.b[k] = e.b[k], g.c0[k] = e.c0[k], g.c1[k] = e.c1[k];
    g.a[3] = float(e.node);
    g.c0[3] = e.sign0;
    g.c1[3] = e.sign1;
    *out++ = g;
  }
  partials_ = vk::Buffer(device, VkDeviceSize(max_batch) * uint32_t(cameras) * groups_ * 2 * sizeof(float),
                         VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, vk::MemoryUse::Readback);
  per_edge_ = vk::Buffer(device, VkDeviceSize(std::max(1u, edge_count_)) * uint32_t(cameras) * 2 * sizeof(float),
                         VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, vk::MemoryUse::Readback);
  auto binding = [](uint32_t b, VkDescriptorType type) {
    return VkDescriptorSetLayoutBinding{b, type, 1, VK_SHADER_STAGE_COMPUTE_BIT, nullptr};
  };
  const std::vector<VkDescriptorSetLayoutBinding> layout_bindings = {
      binding(0, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER),         binding(1, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER),
      binding(2, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER),         binding(3, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER),
      binding(4, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER), binding(5, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER),
      binding(6, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER)};
  set_layout_ = CreateDescriptorSetLayout(device, layout_bindings);
  layout_ = CreatePipelineLayout(device, set_layout_, sizeof(EdgePush), VK_SHADER_STAGE_COMPUTE_BIT);
  DescriptorSets sets = AllocateDescriptorSets(device, set_layout_, layout_bindings, uint32_t(bindings));
  pool_ = std::move(sets.pool);
  sets_ = std::move(sets.sets);
  for (VkDescriptorSet set : sets_) {
    WriteStorageBuffer(device, set, 0, scene.node_matrices());
    WriteStorageBuffer(device, set, 1, edges_);
    WriteStorageBuffer(device, set, 2, partials_);
    WriteStorageBuffer(device, set, 6, per_edge_);
  }
  checks_validity_.assign(size_t(bindings), false);
  const vk::ShaderModule shader = vk::CreateShaderModule(device, kEdgesComp, sizeof(kEdgesComp));
  const float tolerance = float(depth_tolerance);
  uint32_t tolerance_bits = 0;
  std::memcpy(&tolerance_bits, &tolerance, sizeof(tolerance_bits));
  pipeline_ = CreateSubgroupComputePipeline(device, shader, layout_, {0u, kSamples, tolerance_bits});
  validity_pipeline_ = CreateSubgroupComputePipeline(device, shader, layout_, {1u, kSamples, tolerance_bits});
}

void EdgePass::BindImages(int index, VkImageView reference, VkImageView depth, VkImageView validity) {
  WriteSampledImage(*device_, sets_.at(size_t(index)), 3, reference, trilinear_, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
  WriteSampledImage(*device_, sets_.at(size_t(index)), 4, depth, nearest_, VK_IMAGE_LAYOUT_DEPTH_READ_ONLY_OPTIMAL);
  // Without validity the pipeline specialised not to read binding 5 runs; the binding still
  // needs a view, and the reference is one at hand.
  checks_validity_.at(size_t(index)) = validity != VK_NULL_HANDLE;
  WriteSampledImage(*device_, sets_.at(size_t(index)), 5, validity ? validity : reference, trilinear_,
                    VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
}

void EdgePass::record(VkCommandBuffer cmd, const ViewCamera& camera_view, const Eigen::Vector2d& size,
                      const EdgeStatistic& statistic, int binding, int slot, int camera, bool dump) const {
  if (edge_count_ == 0) return;
  EdgePush push{};
  const Eigen::Matrix4f clip = camera_view.clip_from_world.cast<float>();
  std::memcpy(push.clip_from_world, clip.data(), sizeof(push.clip_from_world));
  for (int k = 0; k < 3; ++k) push.centre[k] = float(camera_view.centre[k]);
  push.centre[3] = float(kDefaultNear);
  push.image[0] = float(size.x());
  push.image[1] = float(size.y());
  push.image[2] = float(camera_view.level);
  push.image[3] = float(std::exp2(camera_view.level) / std::sqrt(camera_view.fx_fy));
  const double v = statistic.variance;
  push.statistic[0] = float(1.0 / (2.0 * v));
  push.statistic[1] = float(std::log1p(-statistic.clutter) - 1.5 * std::log(2.0 * kPi * v));
  push.statistic[2] = float(statistic.clutter);
  push.statistic[3] = float(statistic.hidden);
  push.node_offset = scene_->node_offset(slot);
  push.edge_count = edge_count_;
  push.dump_camera = dump ? uint32_t(camera) + 1 : 0;
  push.partial_offset = (uint32_t(slot) * uint32_t(cameras_) + uint32_t(camera)) * groups_;
  const VkPipeline pipeline = checks_validity_.at(size_t(binding)) ? validity_pipeline_ : pipeline_;
  vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, pipeline);
  vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, layout_, 0, 1, &sets_.at(size_t(binding)), 0, nullptr);
  vkCmdPushConstants(cmd, layout_, VK_SHADER_STAGE_COMPUTE_BIT, 0, sizeof(push), &push);
  vkCmdDispatch(cmd, groups_, 1, 1);
}

void EdgePass::record_finish(VkCommandBuffer cmd) const {
  vk::MemoryBarrier(cmd, VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT, VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT,
                    VK_PIPELINE_STAGE_2_HOST_BIT, VK_ACCESS_2_HOST_READ_BIT);
}

Eigen::Vector2d EdgePass::Result(int slot, int camera) const {
  if (edge_count_ == 0) return Eigen::Vector2d::Zero();
  const float* p = partials_.data<float>() + size_t((uint32_t(slot) * uint32_t(cameras_) + uint32_t(camera)) * groups_) * 2;
  Eigen::Vector2d sum = Eigen::Vector2d::Zero();
  for (uint32_t g = 0; g < groups_; ++g) sum += Eigen::Vector2d(p[2 * g], p[2 * g + 1]);
  return sum;
}

Image EdgePass::PerEdge() const {
  Image out(int(std::max(1u, edge_count_)), cameras_);
  if (edge_count_ == 0) return out;
  const float* p = per_edge_.data<float>();
  for (int c = 0; c < cameras_; ++c)
    for (uint32_t e = 0; e < edge_count_; ++e) {
      const size_t k = size_t(c) * edge_count_ + e;
      out.At(int(e), c)[0] = p[2 * k];
      out.At(int(e), c)[1] = p[2 * k + 1];
    }
  return out;
}

}  // namespace vkr
