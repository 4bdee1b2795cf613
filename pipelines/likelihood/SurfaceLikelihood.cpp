#include "pipelines/likelihood/SurfaceLikelihood.h"

#include <cmath>
#include <cstring>
#include <stdexcept>

#include "engine/common/InputError.h"
#include "pipelines/model/LikelihoodSettings.h"
#include "engine/geometry/SceneGeometry.h"
#include "engine/image/Pyramid.h"
#include "engine/vk/Commands.h"
#include "pipelines/passes/CompositePass.h"
#include "pipelines/passes/DepthPass.h"
#include "pipelines/passes/EdgePass.h"
#include "pipelines/passes/GpuScene.h"
#include "pipelines/passes/ViewTexel.h"
#include "pipelines/passes/InteriorPass.h"
#include "pipelines/passes/Projection.h"
#include "pipelines/likelihood/MemoryPlan.h"
#include "pipelines/likelihood/ReferenceImages.h"
#include "pipelines/passes/ViewTexturePass.h"

namespace vkr {

bool SurfaceLikelihoodOptions::IsValid(std::string* why) const {
  auto fail = [&](const std::string& w) {
    if (why) *why = w;
    return false;
  };
  if (!(model.sigma > 0.0)) return fail("sigma must be > 0");
  if (!(model.outlier_chi2 > 0.0)) return fail("outlier_chi2 must be > 0");
  if (atlas < 16 || (atlas & (atlas - 1)) != 0) return fail("atlas must be a power of two ≥ 16");
  if (levels < 1 || (atlas >> (levels - 1)) < 16) return fail("too many levels for the atlas size");
  if (max_batch < 1) return fail("max_batch must be ≥ 1");
  if (!(depth_tolerance >= 0.0 && depth_tolerance < 0.5)) return fail("depth_tolerance must be in [0, 0.5)");
  if (!(model.position_sd >= 0.0 && model.position_sd <= 10.0)) return fail("position_sd must be in [0, 10] pixels");
  if (!(edge_model.hidden > 0.0 && edge_model.hidden < 1.0)) return fail("edge_model.hidden must be in (0, 1)");
  if (!(edge_model.min_clutter > 0.0 && edge_model.min_clutter <= edge_model.max_clutter &&
        edge_model.max_clutter < 1.0))
    return fail("edge_model's clutter bounds must satisfy 0 < min ≤ max < 1");
  return true;
}

SurfaceLikelihoodOptions ResolveSlotImages(const SurfaceLikelihoodOptions& options, const Scene& scene,
                                           const vk::Device& device) {
  SurfaceLikelihoodOptions o = options;
  if (o.slot_images != SlotImages::Auto) return o;
  // A CPU device runs one hypothesis at a time whatever the barriers say (lavapipe), so
  // copies would cost memory for nothing; a GPU gets them where they fit.
  o.slot_images = SlotImages::Shared;
  if (device.is_cpu() || o.max_batch == 1) return o;
  SurfaceLikelihoodOptions per_slot = o;
  per_slot.slot_images = SlotImages::PerSlot;
  if (WhyItDoesNotFit(PlanSurfaceLikelihood(scene, per_slot, device.subgroup_size()), MemoryLimits::Of(device)).empty())
    o.slot_images = SlotImages::PerSlot;
  return o;
}

SurfaceLikelihoodOptions SurfaceLikelihoodOptions::FromScene(const Scene& scene) {
  const LikelihoodSettings settings = ResolvedLikelihood(scene);
  SurfaceLikelihoodOptions o;
  o.model.sigma = settings.sigma;
  o.model.position_sd = settings.position_sd;
  o.weights = settings.weights;
  o.photometric = settings.photometric;
  o.atlas = settings.atlas;
  o.levels = settings.levels;
  o.charts = settings.charts;
  o.edges = settings.edges;
  o.slot_images = settings.slot_images;
  return o;
}

namespace surface_detail {

// One camera's images on the GPU.
struct CameraImages {
  vk::GpuImage reference;           // RGBA8, encoded colour, mip m = pyramid level m
  vk::GpuImage validity;            // R8, the reference's mips: 1 = comparable (none: every pixel is)
  Image own_validity;               // the camera's mask and lens frame (empty: all valid), before clutter
  int width = 0, height = 0;
  // Per pyramid level, neighbouring pixels' differences: the edge term's ε (EdgeEvidence.h).
  std::vector<PairContrasts> pair_contrasts;
};

// What one hypothesis of a submission writes and reads back: its cameras' depth maps, the
// view layers and the interior mask. Shared by every slot of a batch (the hypotheses then
// follow one another, ordered by barriers), or one set per slot so that a GPU may overlap
// them (SlotImages::PerSlot).
struct SlotImages {
  vk::GpuImage views, mask;
  std::vector<vk::ImageView> view_layers;
  std::vector<std::vector<vk::GpuImage>> depth;  // [camera][level], D32F
  bool defined = false;  // the view layers have been cleared once
};

}  // namespace surface_detail

namespace {

constexpr int kTimestampsPerHypothesis = 5;  // start, depth, view, interior, composite

// The passes that read a depth map: the view pass, and the edge pass.
constexpr VkPipelineStageFlags2 kDepthReaders =
    VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT | VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT;


}  // namespace

struct SurfaceLikelihood::Impl {
  vk::Device* device;
  const Scene* scene;
  SurfaceLikelihoodOptions options;
  SceneGeometry geometry;
  vk::Transfer transfer;
  vk::CommandContext context;
  GpuScene gpu_scene;
  std::vector<surface_detail::CameraImages> cameras;
  std::vector<surface_detail::SlotImages> slots;  // one, or one per hypothesis slot
  DepthPass depth_pass;
  std::unique_ptr<ViewTexturePass> view_pass;
  InteriorPass interior_pass;
  ViewCulling culling;
  std::unique_ptr<CompositePass> composite_pass;
  std::unique_ptr<EdgePass> edge_pass;  // null where the edge term is off
  std::unique_ptr<vk::TimestampQueries> timestamps;
  PhotometricCorrection photometric;
  int level = 0;
  int last_batch = 0;

  Impl(vk::Device& d, const Scene& s, const SurfaceLikelihoodOptions& o)
      : device(&d),
        scene(&s),
        options(o),
        geometry(BuildSceneGeometry(s, s.InitialValues(), o.atlas, o.charts)),
        transfer(d),
        context(d),
        gpu_scene(d, transfer, geometry, o.max_batch),
        depth_pass(d, gpu_scene),
        interior_pass(d, s, geometry, gpu_scene),
        culling(geometry) {}

  uint32_t LevelAtlas() const { return uint32_t(options.atlas >> level); }

  // Camera i's images, at every level, for the view pass (at creation, and when its
  // validity changes: between submissions, never while one is in flight).
  void BindCamera(int i) {
    for (size_t s = 0; s < slots.size(); ++s)
      for (int l = 0; l < options.levels; ++l) {
        view_pass->BindImages(ViewBinding(int(s), i, l), cameras[size_t(i)].reference.view(),
                              slots[s].depth[size_t(i)][size_t(l)].view(), cameras[size_t(i)].validity.view());
        if (edge_pass)
          edge_pass->BindImages(ViewBinding(int(s), i, l), cameras[size_t(i)].reference.view(),
                                slots[s].depth[size_t(i)][size_t(l)].view(), cameras[size_t(i)].validity.view());
      }
  }

  // Camera i's edge statistic at the current level and σ: a difference of two pixels of the
  // level, each averaging 4^level pixels of noise σ.
  EdgeStatistic EdgeStatisticOf(int i) const {
    EdgeStatistic s;
    const double sigma = options.model.sigma / 255.0;
    s.variance = 2.0 * sigma * sigma / std::exp2(2.0 * level);
    s.clutter = ClutterShare(cameras[size_t(i)].pair_contrasts[size_t(level)], s.variance, options.edge_model);
    s.hidden = options.edge_model.hidden;
    return s;
  }

  // The view pass's image set of camera i at level l for the images of `slot_images`.
  int ViewBinding(int slot_images, int i, int l) const {
    return (slot_images * int(cameras.size()) + i) * options.levels + l;
  }
  // The images hypothesis slot `slot` uses.
  int ImagesOf(int slot) const { return slots.size() > 1 ? slot : 0; }

  ViewCamera LevelCamera(const Camera& camera) const {
    ViewCamera v;
    v.clip_from_world = ClipFromWorld(camera);
    v.centre = camera.Centre();
    v.fx_fy = camera.K(0, 0) * camera.K(1, 1);
    v.level = level;
    return v;
  }

  void Timestamp(VkCommandBuffer cmd, uint32_t index) const {
    if (!timestamps) return;
    timestamps->Write(cmd, index);
    // Without this the timestamp may be taken before the work it follows (LAVAPIPE.md).
    vk::MemoryBarrier(cmd, VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT, 0, VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT, 0);
  }

  // `dump`: zero the view layers first (a dump's layers read zero off the charts) and write
  // the composite's images. A slot's layers are also zeroed once, at their first use, as a
  // precaution; otherwise nothing off the charts is ever read, and every chart texel is
  // written (ViewTexturePass.cpp).
  void RecordHypothesis(VkCommandBuffer cmd, int slot, const std::vector<Camera>& cams,
                        const std::vector<Eigen::Matrix4d>& world_from_node, bool dump) const {
    const uint32_t ts = uint32_t(slot) * kTimestampsPerHypothesis;
    Timestamp(cmd, ts);
    const int images = ImagesOf(slot);
    const surface_detail::SlotImages& own = slots[size_t(images)];
    // Shared images were read by the previous hypothesis of this submission: each write
    // waits for those reads. A slot's own images were last used by an earlier, fenced
    // submission: they need their layouts only, and no wait, so a GPU may overlap slots.
    const bool shared = slots.size() == 1;
    std::vector<ViewCamera> views_at_level;
    for (size_t i = 0; i < cams.size(); ++i) {
      views_at_level.push_back(LevelCamera(cams[i]));
      const vk::GpuImage& depth = own.depth[i][size_t(level)];
      // The previous hypothesis's view pass read this depth map: write after read.
      vk::ImageBarrier(cmd, depth, VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL,
                       shared ? kDepthReaders : VK_PIPELINE_STAGE_2_NONE, 0,
                       VK_PIPELINE_STAGE_2_EARLY_FRAGMENT_TESTS_BIT | VK_PIPELINE_STAGE_2_LATE_FRAGMENT_TESTS_BIT,
                       VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_READ_BIT | VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT);
      depth_pass.record(cmd, views_at_level.back().clip_from_world, slot, depth);
      vk::ImageBarrier(cmd, depth, VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL,
                       VK_IMAGE_LAYOUT_DEPTH_READ_ONLY_OPTIMAL, VK_PIPELINE_STAGE_2_LATE_FRAGMENT_TESTS_BIT,
                       VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT, kDepthReaders,
                       VK_ACCESS_2_SHADER_SAMPLED_READ_BIT);
    }
    Timestamp(cmd, ts + 1);
    // The previous hypothesis's composite read the views and the mask: write after read.
    for (const vk::GpuImage* image : {&own.views, &own.mask})
      vk::ImageBarrier(cmd, *image, VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL,
                       shared ? VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT : VK_PIPELINE_STAGE_2_NONE, 0,
                       VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT, VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT);
    for (size_t i = 0; i < cams.size(); ++i) {
      const ViewDraws draws = options.cull_views ? culling.Classify(world_from_node, views_at_level[i].clip_from_world,
                                                                    views_at_level[i].centre, kDefaultNear)
                                                 : culling.ShadeAll();
      view_pass->record(cmd, views_at_level[i], draws, ViewBinding(images, int(i), level), slot, own.view_layers[i],
                        LevelAtlas(), dump || !own.defined);
    }
    if (edge_pass)
      for (size_t i = 0; i < cams.size(); ++i) {
        const Eigen::Vector2d size(cameras[i].width, cameras[i].height);
        edge_pass->record(cmd, views_at_level[i], size / std::exp2(level), EdgeStatisticOf(int(i)),
                          ViewBinding(images, int(i), level), slot, int(i), dump);
      }
    Timestamp(cmd, ts + 2);
    interior_pass.record(cmd, slot, own.mask, LevelAtlas());
    Timestamp(cmd, ts + 3);
    for (const vk::GpuImage* image : {&own.views, &own.mask})
      vk::ImageBarrier(cmd, *image, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL, VK_IMAGE_LAYOUT_GENERAL,
                       VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT, VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT,
                       VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT, VK_ACCESS_2_SHADER_STORAGE_READ_BIT);
    if (dump)  // the previous dump's readback is done (fenced); only order against this write
      vk::MemoryBarrier(cmd, VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT, VK_ACCESS_2_MEMORY_READ_BIT,
                        VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT, VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT);
    composite_pass->record(cmd, slot, images, LevelAtlas(), options.model, dump);
    Timestamp(cmd, ts + 4);
  }

  std::vector<Evaluation> Run(const std::vector<std::vector<double>>& batch, bool dump) {
    if (batch.empty()) return {};
    if (int(batch.size()) > options.max_batch)
      throw std::invalid_argument("SurfaceLikelihood::Evaluate: batch of " + std::to_string(batch.size()) +
                                  " exceeds max_batch " + std::to_string(options.max_batch));
    std::vector<std::vector<Camera>> cams(batch.size());
    std::vector<std::vector<Eigen::Matrix4d>> world(batch.size());
    for (size_t k = 0; k < batch.size(); ++k) {
      if (batch[k].size() != scene->parameters.size())
        throw std::invalid_argument("SurfaceLikelihood::Evaluate: hypothesis has the wrong length");
      world[k] = scene->WorldFromNode(batch[k]);
      gpu_scene.SetNodeMatrices(int(k), world[k]);
      interior_pass.SetNodeMatrices(int(k), world[k]);
      cams[k] = scene->Cameras(batch[k]);
    }
    VkCommandBuffer cmd = context.Begin();
    if (timestamps) timestamps->Reset(cmd);
    for (size_t k = 0; k < batch.size(); ++k) RecordHypothesis(cmd, int(k), cams[k], world[k], dump);
    composite_pass->record_reduce(cmd, int(batch.size()), LevelAtlas());
    if (edge_pass) edge_pass->record_finish(cmd);
    if (timestamps) timestamps->Write(cmd, uint32_t(batch.size()) * kTimestampsPerHypothesis);
    context.SubmitAndWait();
    for (size_t k = 0; k < batch.size(); ++k) slots[size_t(ImagesOf(int(k)))].defined = true;
    last_batch = int(batch.size());
    std::vector<Evaluation> out;
    for (size_t k = 0; k < batch.size(); ++k) {
      Evaluation e = Score(composite_pass->Result(int(k)), options.model);
      if (edge_pass)
        for (size_t i = 0; i < cameras.size(); ++i) {
          const Eigen::Vector2d sums = edge_pass->Result(int(k), int(i));
          e.log_edges += sums.x();
          e.edge_length += sums.y();
        }
      out.push_back(e);
    }
    return out;
  }
};

SurfaceLikelihood::SurfaceLikelihood(vk::Device& device, const Scene& scene,
                                     const SurfaceLikelihoodOptions& options) {
  std::string why;
  if (!options.IsValid(&why)) throw std::invalid_argument("SurfaceLikelihoodOptions: " + why);
  if (scene.cameras.size() < 2)
    throw InputError(scene.file.string(), "cameras", "the surface likelihood needs at least 2 cameras");
  const SurfaceLikelihoodOptions resolved = ResolveSlotImages(options, scene, device);
  RequireSurfaceLikelihoodFits(scene, resolved, device);  // before anything is allocated
  impl_ = std::make_unique<Impl>(device, scene, resolved);
  Impl& m = *impl_;
  const int levels = options.levels, n = int(scene.cameras.size());
  for (int i = 0; i < n; ++i) {
    const CameraPhoto photo = LoadCameraPhoto(scene, i, levels);
    const Image& image = photo.image;
    surface_detail::CameraImages images;
    images.reference = UploadReference(device, m.transfer, image);
    images.validity = UploadValidity(device, m.transfer, photo);
    images.own_validity = photo.validity;
    images.width = image.width;
    images.height = image.height;
    if (options.edges) {
      const std::vector<Image> pyramid = BuildPyramid(image, levels);
      const std::vector<Image> validity =
          photo.validity.Empty() ? std::vector<Image>(size_t(levels)) : BuildValidityPyramid(photo.validity, levels);
      for (int l = 0; l < levels; ++l) images.pair_contrasts.emplace_back(pyramid[size_t(l)], validity[size_t(l)]);
    }
    m.cameras.push_back(std::move(images));
  }
  const uint32_t atlas = uint32_t(options.atlas);
  const int slot_sets = resolved.slot_images == SlotImages::PerSlot ? options.max_batch : 1;
  std::vector<CompositePass::Inputs> composite_inputs;
  for (int k = 0; k < slot_sets; ++k) {
    surface_detail::SlotImages& slot = m.slots.emplace_back();
    slot.views = vk::GpuImage(device, {atlas, atlas, uint32_t(n), ViewTexturePass::kFormat,
                                       VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_STORAGE_BIT |
                                           VK_IMAGE_USAGE_TRANSFER_SRC_BIT, true});
    slot.mask = vk::GpuImage(device, {atlas, atlas, 1, InteriorPass::kFormat,
                                      VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_STORAGE_BIT});
    for (int i = 0; i < n; ++i) {
      slot.view_layers.push_back(vk::CreateLayerView(device, slot.views, uint32_t(i)));
      auto& depth = slot.depth.emplace_back();
      for (int l = 0; l < levels; ++l) {
        // Shadow maps at each level's resolution (any size works: they are looked up in
        // normalised coordinates).
        const int width = m.cameras[size_t(i)].width, height = m.cameras[size_t(i)].height;
        const uint32_t w = uint32_t(std::max(1, (width + (1 << l) - 1) >> l));
        const uint32_t h = uint32_t(std::max(1, (height + (1 << l) - 1) >> l));
        depth.emplace_back(device, vk::GpuImageInfo{w, h, 1, DepthPass::kFormat,
                                                    VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT | VK_IMAGE_USAGE_SAMPLED_BIT});
      }
    }
  }
  for (const surface_detail::SlotImages& slot : m.slots) composite_inputs.push_back({&slot.views, &slot.mask});
  m.view_pass = std::make_unique<ViewTexturePass>(device, m.gpu_scene, slot_sets * n * levels,
                                                  options.weights == ViewWeights::Angle, options.depth_tolerance);
  if (options.edges)
    m.edge_pass = std::make_unique<EdgePass>(device, m.gpu_scene, FindModelEdges(m.geometry), slot_sets * n * levels,
                                             n, options.max_batch, options.depth_tolerance);
  for (int i = 0; i < n; ++i) m.BindCamera(i);
  m.composite_pass = std::make_unique<CompositePass>(device, composite_inputs, m.geometry.atlas, levels,
                                                    options.max_batch);
  m.photometric = PhotometricCorrection::Identity(n);
  if (options.profile)
    m.timestamps = std::make_unique<vk::TimestampQueries>(
        device, uint32_t(options.max_batch * kTimestampsPerHypothesis + 1));
}

SurfaceLikelihood::~SurfaceLikelihood() = default;

void SurfaceLikelihood::SetSigma(double sigma_255) {
  if (!(std::isfinite(sigma_255) && sigma_255 > 0.0))
    throw std::invalid_argument("SurfaceLikelihood::SetSigma: sigma must be > 0");
  impl_->options.model.sigma = sigma_255;
}

void SurfaceLikelihood::SetPositionSd(double pixels) {
  if (!(std::isfinite(pixels) && pixels >= 0.0))
    throw std::invalid_argument("SurfaceLikelihood::SetPositionSd: must be ≥ 0");
  impl_->options.model.position_sd = pixels;
}

void SurfaceLikelihood::SetPhotometric(const PhotometricCorrection& correction) {
  impl_->composite_pass->SetPhotometric(correction);
  impl_->photometric = correction;
}

const PhotometricCorrection& SurfaceLikelihood::photometric() const { return impl_->photometric; }

void SurfaceLikelihood::SetClutterMasks(const std::vector<Image>& masks) {
  Impl& m = *impl_;
  if (masks.size() != m.cameras.size())
    throw std::invalid_argument("SurfaceLikelihood::SetClutterMasks: one mask per camera expected");
  for (size_t i = 0; i < masks.size(); ++i) {
    surface_detail::CameraImages& camera = m.cameras[i];
    if (masks[i].width != camera.width || masks[i].height != camera.height)
      throw std::invalid_argument("SurfaceLikelihood::SetClutterMasks: a mask of another size than its photograph");
    Image validity = masks[i];
    if (!camera.own_validity.Empty())
      for (size_t k = 0; k < validity.rgba.size(); ++k) validity.rgba[k] *= camera.own_validity.rgba[k];
    camera.validity = UploadValidity(*m.device, m.transfer, validity);
    m.BindCamera(int(i));
  }
}

void SurfaceLikelihood::ClearClutterMasks() {
  Impl& m = *impl_;
  for (size_t i = 0; i < m.cameras.size(); ++i) {
    m.cameras[i].validity = UploadValidity(*m.device, m.transfer, m.cameras[i].own_validity);
    m.BindCamera(int(i));
  }
}

void SurfaceLikelihood::SetLevel(int level) {
  if (level < 0 || level >= impl_->options.levels)
    throw std::out_of_range("SurfaceLikelihood::SetLevel: level " + std::to_string(level) + " of " +
                            std::to_string(impl_->options.levels));
  impl_->level = level;
}

int SurfaceLikelihood::level() const { return impl_->level; }
int SurfaceLikelihood::levels() const { return impl_->options.levels; }
const SurfaceLikelihoodOptions& SurfaceLikelihood::options() const { return impl_->options; }
const Scene& SurfaceLikelihood::scene() const { return *impl_->scene; }
const SceneGeometry& SurfaceLikelihood::geometry() const { return impl_->geometry; }

std::vector<Evaluation> SurfaceLikelihood::Evaluate(const std::vector<std::vector<double>>& batch) {
  return impl_->Run(batch, false);
}

SurfaceDump SurfaceLikelihood::EvaluateAndDump(const std::vector<double>& psi, Evaluation* evaluation) {
  Impl& m = *impl_;
  const Evaluation e = m.Run({psi}, true)[0];
  if (evaluation) *evaluation = e;
  const int size = int(m.LevelAtlas()), full = m.options.atlas;
  auto crop = [&](const std::vector<float>& rgba) {
    Image out(size, size);
    for (int y = 0; y < size; ++y)
      std::memcpy(out.At(0, y), &rgba[size_t(y) * full * 4], size_t(size) * 4 * sizeof(float));
    return out;
  };
  SurfaceDump dump;
  std::vector<uint32_t> words(size_t(full) * full * 2);
  std::vector<float> floats(size_t(full) * full * 4), noise(floats.size(), 0.0f);
  const vk::GpuImage& views = m.slots[0].views;  // the dump's one hypothesis is slot 0's
  for (uint32_t i = 0; i < views.info().layers; ++i) {
    m.transfer.ReadImage(views, i, VK_IMAGE_LAYOUT_GENERAL, words.data());
    for (size_t k = 0; k < size_t(full) * full; ++k) {
      const ViewTexel t = UnpackViewTexel(words[2 * k], words[2 * k + 1]);
      for (int c = 0; c < 3; ++c) floats[4 * k + size_t(c)] = t.colour[c];
      floats[4 * k + 3] = noise[4 * k + 3] = t.weight;
      noise[4 * k] = t.texture;
      noise[4 * k + 1] = t.mass;
    }
    dump.view_textures.push_back(crop(floats));
    dump.view_noise.push_back(crop(noise));
  }
  m.transfer.ReadImage(m.composite_pass->composite(), 0, VK_IMAGE_LAYOUT_GENERAL, floats.data());
  dump.composite = crop(floats);
  m.transfer.ReadImage(m.composite_pass->deviation(), 0, VK_IMAGE_LAYOUT_GENERAL, floats.data());
  dump.deviation = crop(floats);
  m.transfer.ReadImage(m.composite_pass->noise(), 0, VK_IMAGE_LAYOUT_GENERAL, floats.data());
  dump.noise = crop(floats);
  if (m.edge_pass) dump.edges = m.edge_pass->PerEdge();
  return dump;
}

std::map<std::string, double> SurfaceLikelihood::LastPassTimesMs() const {
  const Impl& m = *impl_;
  std::map<std::string, double> out;
  if (!m.timestamps || m.last_batch == 0) return out;
  const uint32_t count = uint32_t(m.last_batch) * kTimestampsPerHypothesis + 1;
  const std::vector<double> t = m.timestamps->ReadMs(count);
  const char* names[] = {"depth", "view_texture", "interior", "composite"};
  for (int k = 0; k < m.last_batch; ++k)
    for (int p = 0; p < 4; ++p) {
      const size_t i = size_t(k) * kTimestampsPerHypothesis + p;
      out[names[p]] += (t[i + 1] - t[i]) / m.last_batch;
    }
  out["reduce"] = (t[count - 1] - t[count - 2]) / m.last_batch;  // one pass for the batch, per hypothesis like the others
  return out;
}

}  // namespace vkr
