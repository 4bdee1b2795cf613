#include "pipelines/rendering/ViewRendering.h"
#include "pipelines/model/LikelihoodSettings.h"
#include "pipelines/rendering/SynthSettings.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <memory>
#include <nlohmann/json.hpp>
#include <random>

#include "engine/common/InputError.h"
#include "engine/image/Exposure.h"
#include "engine/image/Image.h"
#include "engine/scene/CameraWriter.h"
#include "engine/scene/Colmap.h"
#include "engine/vk/Commands.h"
#include "pipelines/rendering/Environment.h"
#include "pipelines/passes/GpuScene.h"
#include "pipelines/rendering/LensWarp.h"
#include "pipelines/rendering/NodeMask.h"
#include "pipelines/passes/NovelViewPass.h"
#include "pipelines/rendering/SunLight.h"

namespace fs = std::filesystem;

namespace vkr {
namespace {

// Uploads an atlas image as a sampled RGBA32F texture.
vk::GpuImage UploadAtlas(vk::Device& device, vk::Transfer& transfer, const Image& atlas) {
  vk::GpuImage image(device, {uint32_t(atlas.width), uint32_t(atlas.height), 1,
                              VK_FORMAT_R32G32B32A32_SFLOAT,
                              VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT});
  transfer.UploadImage(image, 0, atlas.rgba.data(), VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
  return image;
}

// Everything needed to draw a scene once: geometry on the GPU, an atlas, the pass.
struct SceneDrawer {
  vk::Transfer transfer;
  vk::CommandContext context;
  GpuScene gpu_scene;
  vk::GpuImage atlas;
  NovelViewPass pass;

  SceneDrawer(vk::Device& device, const SceneGeometry& geometry, const Image& atlas_image)
      : transfer(device),
        context(device),
        gpu_scene(device, transfer, geometry),
        atlas(UploadAtlas(device, transfer, atlas_image)),
        pass(device, gpu_scene, atlas) {}
};

fs::path SynthImageName(const Camera& camera) {
  fs::path name = camera.image.filename();
  if (name.empty()) name = camera.name + ".png";
  std::string ext = name.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), ::tolower);
  if (ext != ".png") name.replace_extension(".png");  // synth writes lossless 8-bit images
  return name;
}

// The mask of `nodes` in `camera`'s image, written where LoadScene finds it for a scene
// whose `images` is `images_dir`: masks/<image name>.png beside that folder.
fs::path WriteNodeMask(SceneDrawer& drawer, const Camera& camera, const std::vector<Eigen::Matrix4d>& world_from_node,
                       const std::vector<int>& nodes, const fs::path& images_dir) {
  const Image mask = RenderThroughLens(
      camera,
      [&](const Camera& pinhole) {
        return VisibleNodeMask(
            [&](const std::vector<Eigen::Matrix4d>& world) {
              drawer.gpu_scene.SetNodeMatrices(0, world);
              return drawer.pass.Render(drawer.transfer, drawer.context, pinhole, 0,
                                        NovelViewPass::Output::WorldPosition);
            },
            world_from_node, nodes);
      },
      LensResampling::Conservative);
  drawer.gpu_scene.SetNodeMatrices(0, world_from_node);
  fs::path folder = fs::absolute(images_dir).lexically_normal();
  if (!folder.has_filename()) folder = folder.parent_path();  // "images/" names the folder itself
  const fs::path file = folder.parent_path() / "masks" / (camera.image.filename().string() + ".png");
  WriteMaskPng(file, mask);
  return file;
}

}  // namespace

Camera ScaleCamera(const Camera& camera, double scale) {
  if (scale == 1.0) return camera;
  Camera out = camera;
  out.width = std::max(1, int(std::lround(camera.width * scale)));
  out.height = std::max(1, int(std::lround(camera.height * scale)));
  const double sx = double(out.width) / camera.width, sy = double(out.height) / camera.height;
  out.K.row(0) *= sx;
  out.K.row(1) *= sy;
  return out;
}

namespace {

// The effective photograph settings: the scene's `synth` block under the options' overrides.
SynthSettings EffectiveSynth(const Scene& scene, const SynthOptions& o) {
  SynthSettings s = SynthSettingsOf(scene);
  if (o.sun) s.sun = *o.sun;
  if (o.sun_azimuth) s.sun_azimuth = *o.sun_azimuth;
  if (o.sun_elevation) s.sun_elevation = *o.sun_elevation;
  if (o.ambient) s.ambient = *o.ambient;
  if (o.exposure) s.exposure = *o.exposure;
  if (o.supersample) s.supersample = *o.supersample;
  return s;
}

// Where no surface was drawn, the distant environment shows through (Environment.h).
void FillEnvironment(const Camera& camera, Image& image) {
  const Eigen::Matrix3d ray_from_pixel = camera.R().transpose() * camera.K.inverse();
  for (size_t i = 0; i < image.rgba.size(); i += 4) {
    if (image.rgba[i + 3] != 0.0f) continue;
    const size_t pixel = i / 4;
    const Eigen::Vector3d uv1(double(pixel % image.width) + 0.5, double(pixel / image.width) + 0.5, 1.0);
    const Eigen::Vector3f env = EnvironmentColour(ray_from_pixel * uv1);
    for (int c = 0; c < 3; ++c) image.rgba[i + c] = env[c];
  }
}

// The mean of each n×n block, in linear light: a sensor pixel integrates light.
Image DownsampleLinear(const Image& image, int n) {
  if (n == 1) return image;
  Image out(image.width / n, image.height / n);
  for (int y = 0; y < out.height; ++y)
    for (int x = 0; x < out.width; ++x) {
      double sum[3] = {0, 0, 0};
      for (int dy = 0; dy < n; ++dy)
        for (int dx = 0; dx < n; ++dx) {
          const float* p = image.At(x * n + dx, y * n + dy);
          for (int c = 0; c < 3; ++c) sum[c] += SrgbToLinear(p[c]);
        }
      float* q = out.At(x, y);
      for (int c = 0; c < 3; ++c) q[c] = LinearToSrgb(float(sum[c] / (n * n)));
      q[3] = 1.0f;
    }
  return out;
}

nlohmann::json ExposureJson(const std::vector<Camera>& cameras, const std::vector<Exposure>& exposures) {
  nlohmann::json list = nlohmann::json::array();
  for (size_t i = 0; i < cameras.size(); ++i) {
    const Exposure& e = exposures[i];
    list.push_back({{"camera", cameras[i].name},
                    {"gain", {e.gain[0], e.gain[1], e.gain[2]}},
                    {"offset_255", e.offset * 255.0},
                    {"gamma", e.gamma}});
  }
  return {{"exposures", list}};
}

}  // namespace

SynthSummary SynthesiseImages(const SynthOptions& options, vk::Device& device) {
  if (!(options.scale > 0.0 && options.scale <= 16.0))
    throw InputError("", "--scale", "must be in (0, 16]");
  if (!(options.noise_sigma >= 0.0)) throw InputError("", "--noise", "must be ≥ 0");
  LoadOptions load;
  load.require_images = false;  // synth is what makes them
  const Scene scene = LoadScene(options.scene_file, options.overrides, load);
  const std::vector<double> psi = scene.ValuesFromFile(options.at_file);
  const SynthSettings settings = EffectiveSynth(scene, options);
  SunLight sun{settings.sun_azimuth, settings.sun_elevation, settings.ambient};
  if (std::string why; settings.sun && !sun.IsValid(&why)) throw InputError("", "--sun", why);
  if (!(settings.exposure >= 0.0 && settings.exposure < 1.0)) throw InputError("", "--exposure", "must be in [0, 1)");
  if (settings.supersample < 1 || settings.supersample > 8) throw InputError("", "--supersample", "must be in [1, 8]");

  // Charts as the scene's likelihood lays them out, so the truth's atlas is a run's, larger.
  const SceneGeometry geometry =
      BuildSceneGeometry(scene, scene.InitialValues(), options.atlas, LikelihoodSettingsOf(scene).charts);
  const Image atlas = BakeAlbedoAtlas(geometry.atlas, geometry.meshes, LoadAlbedos(scene));
  SceneDrawer drawer(device, geometry, atlas);
  const std::vector<Eigen::Matrix4d> world_from_node = scene.WorldFromNode(psi);
  drawer.gpu_scene.SetNodeMatrices(0, world_from_node);
  const std::vector<int> masked_nodes = NodeIndices(scene, options.mask_nodes, "--mask-nodes");
  std::unique_ptr<SunShadow> shadow;
  if (settings.sun) {
    shadow = std::make_unique<SunShadow>(device, drawer.gpu_scene);
    const SunLighting lighting = shadow->Render(drawer.context, sun, WorldBounds(scene, psi, geometry).everything);
    drawer.pass.SetSunLighting(lighting, shadow->map());
  }
  const NovelViewPass::Output output = settings.sun ? NovelViewPass::Output::LitColour : NovelViewPass::Output::Colour;

  fs::create_directories(options.output_dir);
  std::mt19937_64 rng(options.seed);
  // Exposures draw from their own stream, so the noise of a seed is the same with and without.
  std::mt19937_64 exposure_rng(options.seed ^ 0x9e3779b97f4a7c15ull);
  std::normal_distribution<double> noise(0.0, options.noise_sigma / 255.0);
  SynthSummary summary;
  std::vector<Camera> written;
  std::vector<Exposure> exposures;
  for (const Camera& scene_camera : scene.Cameras(psi)) {
    Camera camera = ScaleCamera(scene_camera, options.scale);
    if (options.distortion) camera.distortion = *options.distortion;
    // Through a lens: a pinhole view covering the distorted frame, resampled (LensWarp.h);
    // each pinhole pixel the mean of n×n samples.
    const int n = settings.supersample;
    Image image = RenderThroughLens(camera, [&](const Camera& pinhole) {
      Camera fine = pinhole;
      fine.width *= n;
      fine.height *= n;
      fine.K.row(0) *= n;
      fine.K.row(1) *= n;
      Image view = drawer.pass.Render(drawer.transfer, drawer.context, fine, 0, output);
      FillEnvironment(fine, view);
      return DownsampleLinear(view, n);
    });
    const Exposure exposure = settings.exposure > 0.0 ? RandomExposure(settings.exposure, exposure_rng) : Exposure{};
    for (size_t i = 0; i < image.rgba.size(); i += 4) {
      for (int c = 0; c < 3; ++c) {
        double v = exposure.Apply(image.rgba[i + c], c);
        if (options.noise_sigma > 0.0) v += noise(rng);
        image.rgba[i + c] = float(std::clamp(v, 0.0, 1.0));
      }
      image.rgba[i + 3] = 1.0f;  // photographs are opaque
    }
    camera.image = options.output_dir / SynthImageName(camera);
    WritePng(camera.image, image);
    summary.images.push_back(camera.image);
    if (!masked_nodes.empty())
      summary.masks.push_back(WriteNodeMask(drawer, camera, world_from_node, masked_nodes, options.output_dir));
    written.push_back(camera);
    exposures.push_back(exposure);
  }
  summary.cameras_file = options.output_dir / "cameras.json";
  WriteCamerasJson(summary.cameras_file, written);
  if (settings.exposure > 0.0) {
    summary.exposure_file = options.output_dir / "exposure.json";
    std::ofstream out(summary.exposure_file);
    out << ExposureJson(written, exposures).dump(2) << "\n";
  }
  if (options.colmap) {
    summary.colmap_dir = options.output_dir / "sparse";
    WriteColmapText(summary.colmap_dir, written, options.output_dir);
  }
  return summary;
}

SceneBounds WorldBounds(const Scene& scene, const std::vector<double>& psi, const SceneGeometry& geometry) {
  const std::vector<Eigen::Matrix4d> world_from_node = scene.WorldFromNode(psi);
  SceneBounds b;
  for (size_t node = 0; node < geometry.meshes.size(); ++node)
    for (const Eigen::Vector3f& p : geometry.meshes[node].positions) {
      const Eigen::Vector3d w = (world_from_node[node] * p.cast<double>().homogeneous()).head<3>();
      b.everything.extend(w);
      if (scene.nodes[node].primitive != PrimitiveKind::Plane) b.objects.extend(w);
    }
  return b;
}

std::vector<Camera> OrbitCameras(const Scene& scene, const std::vector<double>& psi,
                                 const SceneGeometry& geometry, int n) {
  const std::vector<Camera> cameras = scene.Cameras(psi);
  if (cameras.empty()) throw InputError(scene.file.string(), "cameras", "--orbit needs at least one camera for its intrinsics");
  const SceneBounds bounds = WorldBounds(scene, psi, geometry);
  const Eigen::AlignedBox3d box = bounds.objects.isEmpty() ? bounds.everything : bounds.objects;
  const Eigen::Vector3d centre = box.isEmpty() ? Eigen::Vector3d(Eigen::Vector3d::Zero()) : Eigen::Vector3d(box.center());
  double radius = 0.0, height = 0.0;
  for (const Camera& c : cameras) {
    const Eigen::Vector3d d = c.Centre() - centre;
    radius += d.head<2>().norm() / cameras.size();
    height += d.z() / cameras.size();
  }
  if (radius < 1e-6) radius = std::max(1.0, 2.0 * box.sizes().norm());
  std::vector<Camera> out;
  for (int k = 0; k < n; ++k) {
    const double a = 2.0 * M_PI * k / n;
    const Eigen::Vector3d eye = centre + Eigen::Vector3d(radius * std::cos(a), radius * std::sin(a), height);
    Camera c = cameras.front();
    char name[16];
    std::snprintf(name, sizeof name, "%03d", k);
    c.name = name;
    c.image.clear();
    c.cam_from_world = CamFromWorldLookingAt(eye, centre);
    out.push_back(c);
  }
  return out;
}

std::vector<Image> RenderWithAtlas(vk::Device& device, const Scene& scene, const std::vector<double>& psi,
                                   const SceneGeometry& geometry, const Image& atlas,
                                   const std::vector<Camera>& cameras) {
  SceneDrawer drawer(device, geometry, atlas);
  drawer.gpu_scene.SetNodeMatrices(0, scene.WorldFromNode(psi));
  std::vector<Image> out;
  for (const Camera& camera : cameras)
    out.push_back(RenderThroughLens(
        camera, [&](const Camera& pinhole) { return drawer.pass.Render(drawer.transfer, drawer.context, pinhole); }));
  return out;
}

std::vector<fs::path> RenderViews(const RenderOptions& options, vk::Device& device) {
  if (options.orbit < 0) throw InputError("", "--orbit", "must be ≥ 0");
  LoadOptions load;
  load.require_images = false;  // novel views need no photographs
  const Scene scene = LoadScene(options.scene_file, options.overrides, load);
  const std::vector<double> psi =
      options.at_file ? scene.ValuesFromFile(*options.at_file) : scene.InitialValues();

  Image atlas;
  int atlas_size = options.atlas;
  if (options.texture) {
    atlas = LoadImage(*options.texture);
    if (atlas.width != atlas.height)
      throw InputError(options.texture->string(), "", "an atlas texture must be square, this one is " +
                       std::to_string(atlas.width) + "×" + std::to_string(atlas.height));
    atlas_size = atlas.width;
  }
  // The same layout as the run that made the texture: decided at the initial values.
  const SceneGeometry geometry =
      BuildSceneGeometry(scene, scene.InitialValues(), atlas_size, LikelihoodSettingsOf(scene).charts);
  if (!options.texture) atlas = BakeAlbedoAtlas(geometry.atlas, geometry.meshes, LoadAlbedos(scene));

  std::vector<Camera> views;
  if (options.orbit > 0) {
    views = OrbitCameras(scene, psi, geometry, options.orbit);
  } else {
    const std::vector<Camera> all = scene.Cameras(psi);
    if (options.cameras.empty()) views = all;
    for (const std::string& name : options.cameras) {
      auto it = std::find_if(all.begin(), all.end(), [&](const Camera& c) { return c.name == name; });
      if (it == all.end()) throw InputError(scene.file.string(), "cameras", "no camera named '" + name + "' (--camera)");
      views.push_back(*it);
    }
  }
  for (Camera& c : views) c = ScaleCamera(c, options.scale);

  SceneDrawer drawer(device, geometry, atlas);
  drawer.gpu_scene.SetNodeMatrices(0, scene.WorldFromNode(psi));

  // One view to a .exr path writes exactly there; otherwise a file per view.
  const bool single_file = views.size() == 1 && options.output.extension() == ".exr";
  fs::path folder = single_file ? options.output.parent_path() : options.output;
  std::string prefix;
  if (!single_file && options.output.extension() == ".exr") {
    folder = options.output.parent_path();
    prefix = options.output.stem().string() + "_";
  }
  if (!folder.empty()) fs::create_directories(folder);
  std::vector<fs::path> written;
  for (const Camera& camera : views) {
    const Image image = RenderThroughLens(
        camera, [&](const Camera& pinhole) { return drawer.pass.Render(drawer.transfer, drawer.context, pinhole); });
    const fs::path file = single_file ? options.output : folder / (prefix + camera.name + ".exr");
    WriteExr(file, image);
    written.push_back(file);
    if (options.png) {
      fs::path png = file;
      WritePng(png.replace_extension(".png"), image);
      written.push_back(png);
    }
  }
  return written;
}

}  // namespace vkr
