#include "pipelines/likelihood/ImageLikelihood.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <numeric>
#include <stdexcept>

#include "engine/common/InputError.h"
#include "pipelines/model/LikelihoodSettings.h"
#include "engine/geometry/SceneGeometry.h"
#include "engine/image/Pyramid.h"
#include "engine/vk/Commands.h"
#include "pipelines/passes/DepthPass.h"
#include "pipelines/passes/GpuScene.h"
#include "pipelines/passes/HalfFloat.h"
#include "pipelines/passes/ImageComparePass.h"
#include "pipelines/passes/TargetWarpPass.h"
#include "pipelines/likelihood/MemoryPlan.h"
#include "pipelines/likelihood/ReferenceImages.h"
#include "pipelines/passes/Projection.h"

namespace vkr {

std::vector<CameraPair> SelectPairs(const std::vector<Camera>& cameras, int partners, PartnerRanking ranking) {
  const int n = int(cameras.size());
  const bool all = partners <= 0 || partners >= n - 1;
  std::vector<CameraPair> pairs;
  for (int t = 0; t < n; ++t) {
    std::vector<int> sources;
    for (int s = 0; s < n; ++s)
      if (s != t) sources.push_back(s);
    if (!all) {
      // Smaller is better: centre distance, or 1 − cos of the angle between optical axes.
      auto cost = [&](int s) {
        if (ranking == PartnerRanking::Distance) return (cameras[s].Centre() - cameras[t].Centre()).norm();
        const Eigen::Vector3d axis_s = cameras[s].R().row(2).transpose(), axis_t = cameras[t].R().row(2).transpose();
        return 1.0 - axis_s.dot(axis_t);
      };
      std::stable_sort(sources.begin(), sources.end(), [&](int a, int b) { return cost(a) < cost(b); });
      sources.resize(size_t(partners));
      std::sort(sources.begin(), sources.end());
    }
    for (int s : sources) pairs.push_back({s, t});
  }
  return pairs;
}

bool ImageLikelihoodOptions::IsValid(std::string* why) const {
  auto fail = [&](const std::string& w) {
    if (why) *why = w;
    return false;
  };
  if (!(model.sigma > 0.0)) return fail("sigma must be > 0");
  if (!(model.robust_cap > 0.0)) return fail("robust_cap must be > 0");
  if (partners < 0) return fail("partners must be ≥ 0 (0: all pairs)");
  if (levels < 1 || levels > 12) return fail("levels must be in [1, 12]");
  if (max_batch < 1) return fail("max_batch must be ≥ 1");
  if (!(depth_tolerance >= 0.0 && depth_tolerance < 0.5)) return fail("depth_tolerance must be in [0, 0.5)");
  if (!(position_sd >= 0.0 && position_sd <= 10.0)) return fail("position_sd must be in [0, 10] pixels");
  return true;
}

ImageLikelihoodOptions ImageLikelihoodOptions::FromScene(const Scene& scene) {
  const LikelihoodSettings settings = ResolvedLikelihood(scene);
  ImageLikelihoodOptions o;
  o.model.sigma = settings.sigma;
  o.position_sd = settings.position_sd;
  o.levels = settings.levels;
  o.partners = settings.partners;
  o.ranking = settings.partner_ranking;
  const int others = int(scene.cameras.size()) - 1;
  if (o.partners > others)
    throw InputError(scene.file.string(), "likelihood.partners",
                     std::to_string(o.partners) + " partners, but each camera has " + std::to_string(others) +
                         " others (0 compares all pairs)");
  return o;
}

namespace {

constexpr int kImageTimestamps = 4;  // start, depth, warp, compare
// The atlas is the surface likelihood's; image space only needs the geometry.
constexpr int kImageUnusedAtlas = 1024;

}  // namespace

struct ImageLikelihood::Impl {
  // One draw of the warp pass: a target and some of its sources.
  struct WarpGroup {
    int target = 0;
    std::vector<int> sources;
  };

  // `pairs` (grouped by target, as SelectPairs makes them) as draws of at most `most`
  // sources, a target's sources split evenly over as few draws as take them all.
  static std::vector<WarpGroup> GroupPairs(const std::vector<CameraPair>& pairs, int most) {
    std::vector<WarpGroup> groups;
    for (size_t first = 0; first < pairs.size();) {
      size_t end = first;
      while (end < pairs.size() && pairs[end].target == pairs[first].target) ++end;
      const int count = int(end - first), draws = (count + most - 1) / most;
      for (int d = 0; d < draws; ++d) {
        WarpGroup group{pairs[first].target, {}};
        for (size_t p = first + size_t(count * d / draws); p < first + size_t(count * (d + 1) / draws); ++p)
          group.sources.push_back(pairs[p].source);
        groups.push_back(std::move(group));
      }
      first = end;
    }
    return groups;
  }

  // One camera's images on the GPU.
  struct CameraImages {
    vk::GpuImage reference;           // RGBA8, encoded colour, mip m = pyramid level m, alpha = |∇I|
    vk::GpuImage validity;            // R8, the reference's mips: 1 = comparable (none: every pixel is)
    std::vector<vk::GpuImage> depth;  // D32F, one per likelihood level
    std::vector<VkExtent2D> size;     // the image at each likelihood level
  };

  vk::Device* device;
  const Scene* scene;
  ImageLikelihoodOptions options;
  SceneGeometry geometry;
  vk::Transfer transfer;
  vk::CommandContext context;
  GpuScene gpu_scene;
  std::vector<CameraPair> pairs;
  std::vector<WarpGroup> groups;
  std::vector<CameraImages> cameras;
  vk::GpuImage results;  // one layer per group
  // One layer per pair, made by the first dump: each pair drawn alone, for its own images.
  vk::GpuImage pair_results, synthetic;
  std::vector<vk::ImageView> result_layers, pair_result_layers, synthetic_layers;
  DepthPass depth_pass;
  std::unique_ptr<TargetWarpPass> warp_pass;
  std::unique_ptr<ImageComparePass> compare_pass;
  std::unique_ptr<vk::TimestampQueries> timestamps;
  int level = 0;
  int last_batch = 0;

  // seen_once here counts target pixels that no source sees, compared by no pair: the
  // occlusion prior's charge for surface one view alone sees (Evaluation.h) is the surface
  // likelihood's and does not apply.
  static ImageLikelihoodOptions WithoutUnverifiedCharge(ImageLikelihoodOptions o) {
    o.model.unverified_penalty = 0.0;
    return o;
  }

  Impl(vk::Device& d, const Scene& s, const ImageLikelihoodOptions& o)
      : device(&d),
        scene(&s),
        options(WithoutUnverifiedCharge(o)),
        geometry(BuildSceneGeometry(s, s.InitialValues(), kImageUnusedAtlas, ChartSizing::Area)),
        transfer(d),
        context(d),
        gpu_scene(d, transfer, geometry, o.max_batch),
        pairs(SelectPairs(s.Cameras(s.InitialValues()), o.partners, o.ranking)),
        groups(GroupPairs(pairs, TargetWarpPass::kMaxSources)),
        depth_pass(d, gpu_scene) {}

  // Image sets of the warp pass: per group and level, then per pair and level (dumps).
  int GroupBinding(size_t group, int l) const { return int(group) * options.levels + l; }
  int PairBinding(size_t pair, int l) const { return int(groups.size() + pair) * options.levels + l; }

  TargetWarpPass::Target WarpTarget(int camera, VkImageView result, VkImageView synthetic_view) const {
    const CameraImages& target = cameras[size_t(camera)];
    TargetWarpPass::Target out;
    out.depth = target.depth[size_t(level)].view();
    out.result = result;
    out.synthetic = synthetic_view;
    out.width = target.size[size_t(level)].width;
    out.height = target.size[size_t(level)].height;
    return out;
  }

  void Timestamp(VkCommandBuffer cmd, uint32_t index) const {
    if (!timestamps) return;
    timestamps->Write(cmd, index);
    // Without this the timestamp may be taken before the work it follows (LAVAPIPE.md).
    vk::MemoryBarrier(cmd, VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT, 0, VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT, 0);
  }

  void RecordHypothesis(VkCommandBuffer cmd, int slot, const std::vector<Camera>& cams, bool dump) const {
    constexpr VkPipelineStageFlags2 kTests =
        VK_PIPELINE_STAGE_2_EARLY_FRAGMENT_TESTS_BIT | VK_PIPELINE_STAGE_2_LATE_FRAGMENT_TESTS_BIT;
    const uint32_t ts = uint32_t(slot) * kImageTimestamps;
    Timestamp(cmd, ts);
    for (size_t i = 0; i < cams.size(); ++i) {
      const vk::GpuImage& depth = cameras[i].depth[size_t(level)];
      // The previous hypothesis's warp passes read this depth map (sampled and as the
      // depth attachment): write after read.
      vk::ImageBarrier(cmd, depth, VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL,
                       VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT | kTests, 0, kTests,
                       VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_READ_BIT | VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT);
      depth_pass.record(cmd, ClipFromWorld(cams[i]), slot, depth);
      vk::ImageBarrier(cmd, depth, VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL, VK_IMAGE_LAYOUT_DEPTH_READ_ONLY_OPTIMAL,
                       VK_PIPELINE_STAGE_2_LATE_FRAGMENT_TESTS_BIT, VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT,
                       VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT | kTests,
                       VK_ACCESS_2_SHADER_SAMPLED_READ_BIT | VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_READ_BIT);
    }
    Timestamp(cmd, ts + 1);
    // The previous hypothesis's compare pass read the results: write after read.
    vk::ImageBarrier(cmd, results, VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL,
                     VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT, 0, VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT,
                     VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT);
    for (size_t g = 0; g < groups.size(); ++g)
      warp_pass->record(cmd, slot, level, GroupBinding(g, level),
                        WarpTarget(groups[g].target, result_layers[g], VK_NULL_HANDLE));
    if (dump) RecordPairs(cmd, slot);
    Timestamp(cmd, ts + 2);
    vk::ImageBarrier(cmd, results, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL, VK_IMAGE_LAYOUT_GENERAL,
                     VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT, VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT,
                     VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT, VK_ACCESS_2_SHADER_STORAGE_READ_BIT);
    compare_pass->record(cmd, slot, level, options.model.sigma);
    Timestamp(cmd, ts + 3);
  }

  // A dump's per-pair images: every pair drawn alone into its own layers, after (and apart
  // from) the groups' draws, so that the evaluation does not depend on whether it dumps.
  void RecordPairs(VkCommandBuffer cmd, int slot) const {
    for (const vk::GpuImage* image : {&pair_results, &synthetic})
      vk::ImageBarrier(cmd, *image, VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL,
                       VK_PIPELINE_STAGE_2_NONE, 0, VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT,
                       VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT);
    for (size_t p = 0; p < pairs.size(); ++p)
      warp_pass->record(cmd, slot, level, PairBinding(p, level),
                        WarpTarget(pairs[p].target, pair_result_layers[p], synthetic_layers[p]));
    for (const vk::GpuImage* image : {&pair_results, &synthetic})
      vk::ImageBarrier(cmd, *image, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL, VK_IMAGE_LAYOUT_GENERAL,
                       VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT, VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT,
                       VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT, VK_ACCESS_2_MEMORY_READ_BIT);
  }

  std::vector<Evaluation> Run(const std::vector<std::vector<double>>& batch, bool dump) {
    if (batch.empty()) return {};
    if (int(batch.size()) > options.max_batch)
      throw std::invalid_argument("ImageLikelihood::Evaluate: batch of " + std::to_string(batch.size()) +
                                  " exceeds max_batch " + std::to_string(options.max_batch));
    std::vector<std::vector<Camera>> cams(batch.size());
    for (size_t k = 0; k < batch.size(); ++k) {
      if (batch[k].size() != scene->parameters.size())
        throw std::invalid_argument("ImageLikelihood::Evaluate: hypothesis has the wrong length");
      gpu_scene.SetNodeMatrices(int(k), scene->WorldFromNode(batch[k]));
      cams[k] = scene->Cameras(batch[k]);
      warp_pass->SetCameras(int(k), cams[k]);
    }
    VkCommandBuffer cmd = context.Begin();
    if (timestamps) timestamps->Reset(cmd);
    for (size_t k = 0; k < batch.size(); ++k) RecordHypothesis(cmd, int(k), cams[k], dump);
    compare_pass->record_reduce(cmd, int(batch.size()), level);
    if (timestamps) timestamps->Write(cmd, uint32_t(batch.size()) * kImageTimestamps);
    context.SubmitAndWait();
    last_batch = int(batch.size());
    std::vector<Evaluation> out;
    for (size_t k = 0; k < batch.size(); ++k) out.push_back(Score(compare_pass->Result(int(k)), options.model));
    return out;
  }
};

ImageLikelihood::ImageLikelihood(vk::Device& device, const Scene& scene, const ImageLikelihoodOptions& options) {
  std::string why;
  if (!options.IsValid(&why)) throw std::invalid_argument("ImageLikelihoodOptions: " + why);
  if (scene.cameras.size() < 2)
    throw InputError(scene.file.string(), "cameras", "the image-space likelihood needs at least 2 cameras");
  RequireImageLikelihoodFits(scene, options, device);  // before anything is allocated
  impl_ = std::make_unique<Impl>(device, scene, options);
  Impl& m = *impl_;
  const int levels = options.levels, n = int(scene.cameras.size());
  uint32_t max_width = 1, max_height = 1;
  for (int i = 0; i < n; ++i) {
    const CameraPhoto photo = LoadCameraPhoto(scene, i, levels);
    const Image& image = photo.image;
    Impl::CameraImages images;
    images.reference = UploadReference(device, m.transfer, image);
    images.validity = UploadValidity(device, m.transfer, photo);
    for (int l = 0; l < levels; ++l) {
      // Depth maps at each level's size (Pyramid.h): the warp pass renders t at this size
      // with t's depth map as its depth attachment, so pixel (i, j) is pyramid pixel (i, j).
      const VkExtent2D size{uint32_t(PyramidLevelSize(image.width, l)), uint32_t(PyramidLevelSize(image.height, l))};
      images.size.push_back(size);
      images.depth.emplace_back(device, vk::GpuImageInfo{size.width, size.height, 1, DepthPass::kFormat,
                                                         VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT |
                                                             VK_IMAGE_USAGE_SAMPLED_BIT});
    }
    max_width = std::max(max_width, uint32_t(image.width));
    max_height = std::max(max_height, uint32_t(image.height));
    m.cameras.push_back(std::move(images));
  }

  const uint32_t group_count = uint32_t(m.groups.size()), pair_count = uint32_t(m.pairs.size());
  m.results = vk::GpuImage(device, {max_width, max_height, group_count, TargetWarpPass::kResultFormat,
                                    VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_STORAGE_BIT, true});
  for (uint32_t g = 0; g < group_count; ++g) m.result_layers.push_back(vk::CreateLayerView(device, m.results, g));

  TargetWarpPass::NoiseModel noise;
  noise.sigma_255 = options.model.sigma;
  noise.robust_cap = options.model.robust_cap;
  noise.position_sd = options.position_sd;
  noise.depth_tolerance = options.depth_tolerance;
  m.warp_pass = std::make_unique<TargetWarpPass>(device, m.gpu_scene, n, options.max_batch,
                                                 int(group_count + pair_count) * levels, noise);
  auto views = [&](int camera, int l) {
    const Impl::CameraImages& c = m.cameras[size_t(camera)];
    return TargetWarpPass::CameraViews{camera, c.reference.view(), c.depth[size_t(l)].view(), c.validity.view()};
  };
  std::vector<std::vector<VkExtent2D>> layer_sizes(static_cast<size_t>(levels));
  for (int l = 0; l < levels; ++l) {
    for (size_t g = 0; g < group_count; ++g) {
      std::vector<TargetWarpPass::CameraViews> sources;
      for (int s : m.groups[g].sources) sources.push_back(views(s, l));
      m.warp_pass->BindImages(m.GroupBinding(g, l), views(m.groups[g].target, l), sources, false);
      layer_sizes[size_t(l)].push_back(m.cameras[size_t(m.groups[g].target)].size[size_t(l)]);
    }
    for (size_t p = 0; p < pair_count; ++p)
      m.warp_pass->BindImages(m.PairBinding(p, l), views(m.pairs[p].target, l), {views(m.pairs[p].source, l)}, true);
  }
  m.compare_pass = std::make_unique<ImageComparePass>(device, m.results, layer_sizes, options.max_batch);
  if (options.profile)
    m.timestamps = std::make_unique<vk::TimestampQueries>(
        device, uint32_t(options.max_batch * kImageTimestamps + 1));
}

ImageLikelihood::~ImageLikelihood() = default;

void ImageLikelihood::SetSigma(double sigma_255) {
  if (!(std::isfinite(sigma_255) && sigma_255 > 0.0))
    throw std::invalid_argument("ImageLikelihood::SetSigma: sigma must be > 0");
  impl_->options.model.sigma = sigma_255;
}

void ImageLikelihood::SetLevel(int level) {
  if (level < 0 || level >= impl_->options.levels)
    throw std::out_of_range("ImageLikelihood::SetLevel: level " + std::to_string(level) + " of " +
                            std::to_string(impl_->options.levels));
  impl_->level = level;
}

int ImageLikelihood::level() const { return impl_->level; }
int ImageLikelihood::levels() const { return impl_->options.levels; }
const std::vector<CameraPair>& ImageLikelihood::pairs() const { return impl_->pairs; }
const ImageLikelihoodOptions& ImageLikelihood::options() const { return impl_->options; }
const Scene& ImageLikelihood::scene() const { return *impl_->scene; }

std::vector<Evaluation> ImageLikelihood::Evaluate(const std::vector<std::vector<double>>& batch) {
  return impl_->Run(batch, false);
}

ImageDump ImageLikelihood::EvaluateAndDump(const std::vector<double>& psi, Evaluation* evaluation) {
  Impl& m = *impl_;
  const uint32_t pair_count = uint32_t(m.pairs.size());
  const uint32_t width = m.results.info().width, height = m.results.info().height;
  if (!m.synthetic.handle()) {
    // A diagnostic, not the sampling loop: made once, by the first dump.
    constexpr VkImageUsageFlags kUsage = VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT;
    m.pair_results = vk::GpuImage(*m.device, {width, height, pair_count, TargetWarpPass::kResultFormat, kUsage, true});
    m.synthetic = vk::GpuImage(*m.device, {width, height, pair_count, TargetWarpPass::kSyntheticFormat, kUsage, true});
    for (uint32_t p = 0; p < pair_count; ++p) {
      m.pair_result_layers.push_back(vk::CreateLayerView(*m.device, m.pair_results, p));
      m.synthetic_layers.push_back(vk::CreateLayerView(*m.device, m.synthetic, p));
    }
  }
  const Evaluation e = m.Run({psi}, true)[0];
  if (evaluation) *evaluation = e;
  std::vector<float> results(size_t(width) * height * 4);
  std::vector<uint16_t> halves(results.size());
  ImageDump dump;
  for (uint32_t p = 0; p < pair_count; ++p) {
    const VkExtent2D size = m.cameras[size_t(m.pairs[p].target)].size[size_t(m.level)];
    m.transfer.ReadImage(m.pair_results, p, VK_IMAGE_LAYOUT_GENERAL, results.data());
    m.transfer.ReadImage(m.synthetic, p, VK_IMAGE_LAYOUT_GENERAL, halves.data());
    ImagePairDump d{m.pairs[p], Image(int(size.width), int(size.height)), Image(int(size.width), int(size.height))};
    for (int y = 0; y < int(size.height); ++y)
      for (int x = 0; x < int(size.width); ++x) {
        const size_t i = (size_t(y) * width + x) * 4;
        float* s = d.synthetic.At(x, y);
        for (int c = 0; c < 4; ++c) s[c] = HalfToFloat(halves[i + c]);
        // One source per draw: g is 1 where it compared, b 1 where only t sees the point.
        float* c = d.consistency.At(x, y);
        c[0] = results[i];
        c[1] = 3.0f * results[i + 1];
        c[3] = results[i + 3];
      }
    dump.pairs.push_back(std::move(d));
  }
  return dump;
}

std::map<std::string, double> ImageLikelihood::LastPassTimesMs() const {
  const Impl& m = *impl_;
  std::map<std::string, double> out;
  if (!m.timestamps || m.last_batch == 0) return out;
  const uint32_t count = uint32_t(m.last_batch) * kImageTimestamps + 1;
  const std::vector<double> t = m.timestamps->ReadMs(count);
  const char* names[] = {"depth", "warp", "compare"};
  for (int k = 0; k < m.last_batch; ++k)
    for (int p = 0; p < 3; ++p) {
      const size_t i = size_t(k) * kImageTimestamps + p;
      out[names[p]] += (t[i + 1] - t[i]) / m.last_batch;
    }
  out["reduce"] = (t[count - 1] - t[count - 2]) / m.last_batch;  // one pass for the batch, per hypothesis like the others
  return out;
}

}  // namespace vkr
