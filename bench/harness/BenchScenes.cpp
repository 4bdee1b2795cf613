#include "bench/harness/BenchScenes.h"

#include <nlohmann/json.hpp>

#include <cmath>
#include <cstring>
#include <fstream>
#include <stdexcept>

#include "pipelines/model/LikelihoodSettings.h"
#include "engine/geometry/SceneGeometry.h"
#include "engine/image/Image.h"
#include "engine/scene/CameraWriter.h"
#include "pipelines/rendering/ViewRendering.h"

namespace fs = std::filesystem;

namespace vkr {
namespace {

using Eigen::Vector2f;
using Eigen::Vector3d;
using Eigen::Vector3f;

// A triangle mesh in vkrecon's frame (Z up), one face: every vertex has a texture coordinate.
struct MeshData {
  std::vector<Vector3f> positions, normals;
  std::vector<Vector2f> uv;
  std::vector<uint32_t> indices;

  uint32_t Add(const Vector3f& p, const Vector3f& n, const Vector2f& t) {
    positions.push_back(p);
    normals.push_back(n);
    uv.push_back(t);
    return uint32_t(positions.size() - 1);
  }
  // A quad a b c d, counter-clockwise seen from the side its normal points to.
  void Quad(uint32_t a, uint32_t b, uint32_t c, uint32_t d) { indices.insert(indices.end(), {a, b, c, a, c, d}); }
};

void WriteFile(const fs::path& file, const void* data, size_t bytes) {
  std::ofstream out(file, std::ios::binary);
  if (!out || !out.write(static_cast<const char*>(data), std::streamsize(bytes)) || !out.flush())
    throw std::runtime_error("cannot write " + file.string());
}

void WriteJson(const fs::path& file, const nlohmann::ordered_json& j) {
  const std::string text = j.dump(2) + "\n";
  WriteFile(file, text.data(), text.size());
}

// glTF 2.0 (`stem`.gltf + `stem`.bin). glTF is Y-up and the loader turns (x, y, z) into
// vkrecon's (x, −z, y), so positions and normals go out as (X, Z, −Y).
fs::path WriteGltf(const MeshData& mesh, const fs::path& dir, const std::string& stem) {
  const size_t n = mesh.positions.size();
  std::vector<char> bin;
  auto append = [&](const void* data, size_t bytes) {
    bin.insert(bin.end(), static_cast<const char*>(data), static_cast<const char*>(data) + bytes);
  };
  Vector3f lo = Vector3f::Constant(INFINITY), hi = Vector3f::Constant(-INFINITY);
  for (const Vector3f& p : mesh.positions) {
    const Vector3f g(p.x(), p.z(), -p.y());
    lo = lo.cwiseMin(g);
    hi = hi.cwiseMax(g);
    append(g.data(), 12);
  }
  for (const Vector3f& v : mesh.normals) {
    const Vector3f g(v.x(), v.z(), -v.y());
    append(g.data(), 12);
  }
  for (const Vector2f& t : mesh.uv) append(t.data(), 8);
  append(mesh.indices.data(), mesh.indices.size() * 4);
  WriteFile(dir / (stem + ".bin"), bin.data(), bin.size());

  using J = nlohmann::ordered_json;
  const size_t offsets[] = {0, n * 12, n * 24, n * 32};
  const size_t lengths[] = {n * 12, n * 12, n * 8, mesh.indices.size() * 4};
  J views = J::array(), accessors = J::array();
  for (int k = 0; k < 4; ++k) views.push_back({{"buffer", 0}, {"byteOffset", offsets[k]}, {"byteLength", lengths[k]}});
  accessors.push_back({{"bufferView", 0}, {"componentType", 5126}, {"count", n}, {"type", "VEC3"},
                       {"min", {lo.x(), lo.y(), lo.z()}}, {"max", {hi.x(), hi.y(), hi.z()}}});
  accessors.push_back({{"bufferView", 1}, {"componentType", 5126}, {"count", n}, {"type", "VEC3"}});
  accessors.push_back({{"bufferView", 2}, {"componentType", 5126}, {"count", n}, {"type", "VEC2"}});
  accessors.push_back({{"bufferView", 3}, {"componentType", 5125}, {"count", mesh.indices.size()}, {"type", "SCALAR"}});
  J gltf;
  gltf["asset"] = {{"version", "2.0"}, {"generator", "vkrecon bench"}};
  gltf["scene"] = 0;
  gltf["scenes"] = J::array({{{"nodes", {0}}}});
  gltf["nodes"] = J::array({{{"mesh", 0}}});
  gltf["meshes"] = J::array({{{"primitives", J::array({{{"attributes", {{"POSITION", 0}, {"NORMAL", 1}, {"TEXCOORD_0", 2}}},
                                                         {"indices", 3}, {"mode", 4}}})}}});
  gltf["buffers"] = J::array({{{"uri", stem + ".bin"}, {"byteLength", bin.size()}}});
  gltf["bufferViews"] = views;
  gltf["accessors"] = accessors;
  const fs::path file = dir / (stem + ".gltf");
  WriteJson(file, gltf);
  return file;
}

// Open cylinder side, diameter 1, z ∈ [0, 1]; u = angle / 360°, v = 1 − z (Primitives.cpp).
MeshData Cylinder(int segments, int rings) {
  MeshData m;
  for (int j = 0; j <= rings; ++j)
    for (int i = 0; i <= segments; ++i) {
      const double a = 2.0 * M_PI * (i == segments ? 0 : i) / segments;
      const float z = float(j) / float(rings);
      m.Add(Vector3f(float(0.5 * std::cos(a)), float(0.5 * std::sin(a)), z),
            Vector3f(float(std::cos(a)), float(std::sin(a)), 0.0f), Vector2f(float(i) / float(segments), 1.0f - z));
    }
  const uint32_t row = uint32_t(segments + 1);
  for (int j = 0; j < rings; ++j)
    for (int i = 0; i < segments; ++i) {
      const uint32_t a = uint32_t(j) * row + uint32_t(i);
      m.Quad(a, a + 1, a + 1 + row, a + row);
    }
  return m;
}

// Segments around and rings up for about `triangles` = 2 · segments · rings; about 2.5
// segments per ring (6 × 1 for the smallest, 12 triangles).
std::pair<int, int> CylinderTessellation(int triangles) {
  const int rings = std::max(1, int(std::lround(std::sqrt(std::max(triangles, 12) / 5.0))));
  const int segments = std::max(3, int(std::lround(std::max(triangles, 6) / (2.0 * rings))));
  return {segments, rings};
}

// Whether item k of n belongs to the first `share` of a low-discrepancy order, so that the
// chosen items spread evenly over the grid and their count is about share · n.
bool Chosen(int k, double share) { return std::fmod(0.6180339887498949 * (k + 1), 1.0) < share; }

// 2 m × 2 m at z = 0, `cells`² cells of two triangles; chosen cells face −z.
MeshData Grid(int cells, double share, int* flipped_triangles) {
  MeshData m;
  *flipped_triangles = 0;
  for (int j = 0; j < cells; ++j)
    for (int i = 0; i < cells; ++i) {
      const float x0 = -1.0f + 2.0f * i / cells, x1 = -1.0f + 2.0f * (i + 1) / cells;
      const float y0 = -1.0f + 2.0f * j / cells, y1 = -1.0f + 2.0f * (j + 1) / cells;
      const bool down = Chosen(j * cells + i, share);
      const Vector3f n(0.0f, 0.0f, down ? -1.0f : 1.0f);
      auto v = [&](float x, float y) { return m.Add(Vector3f(x, y, 0.0f), n, Vector2f((x + 1) / 2, (1 - y) / 2)); };
      const uint32_t a = v(x0, y0), b = v(x1, y0), c = v(x1, y1), d = v(x0, y1);
      if (down) {
        m.Quad(a, d, c, b);
        *flipped_triangles += 2;
      } else {
        m.Quad(a, b, c, d);
      }
    }
  return m;
}

// Strips x ∈ [−2, 2] on the ground running along +y, all 10 m long so that every strip has
// the same area in the atlas: chosen strips run from y = −6 (behind cameras at y = −3) to 4,
// the others from −1 to 9, wholly in front.
MeshData Strips(int strips, double share, int* long_strips) {
  MeshData m;
  *long_strips = 0;
  const Vector3f up(0.0f, 0.0f, 1.0f);
  for (int i = 0; i < strips; ++i) {
    const float x0 = -2.0f + 4.0f * i / strips, x1 = -2.0f + 4.0f * (i + 1) / strips;
    const bool crosses = Chosen(i, share);
    *long_strips += crosses ? 1 : 0;
    const float y0 = crosses ? -6.0f : -1.0f, y1 = y0 + 10.0f;
    auto v = [&](float x, float y) { return m.Add(Vector3f(x, y, 0.0f), up, Vector2f((x + 2) / 4, (9 - y) / 15)); };
    m.Quad(v(x0, y0), v(x1, y0), v(x1, y1), v(x0, y1));
  }
  return m;
}

// A camera at `eye` looking at `target`, OpenCV axes (z forward, x right, y down), with a
// focal length of 0.9375 · width (600 px at 640 wide) and the principal point centred.
Camera LookAt(const std::string& name, const Vector3d& eye, const Vector3d& target, int width, int height) {
  Camera c;
  c.name = name;
  c.image = name + ".png";
  c.width = width;
  c.height = height;
  const double f = 0.9375 * width;
  c.K << f, 0, 0.5 * width, 0, f, 0.5 * height, 0, 0, 1;
  c.cam_from_world = CamFromWorldLookingAt(eye, target);
  return c;
}

std::string CameraName(int k) {
  char name[16];
  std::snprintf(name, sizeof name, "cam%02d", k);
  return name;
}

// Value noise in colour, so every view sees structure (a flat colour would make every
// hypothesis equally photo-consistent and skip nothing either way).
void WriteTexture(const fs::path& file) {
  constexpr int kSize = 256, kCell = 16;
  auto hash = [](int x, int y, int c) {
    uint32_t h = uint32_t(x) * 73856093u ^ uint32_t(y) * 19349663u ^ uint32_t(c) * 83492791u;
    h ^= h >> 13;
    h *= 0x5bd1e995u;
    h ^= h >> 15;
    return float(h & 0xffff) / 65535.0f;
  };
  Image image(kSize, kSize, 1.0f);
  for (int y = 0; y < kSize; ++y)
    for (int x = 0; x < kSize; ++x) {
      const float fx = float(x) / kCell, fy = float(y) / kCell;
      const int ix = int(fx), iy = int(fy);
      const float tx = fx - ix, ty = fy - iy;
      for (int c = 0; c < 3; ++c) {
        const float top = hash(ix, iy, c) * (1 - tx) + hash(ix + 1, iy, c) * tx;
        const float bottom = hash(ix, iy + 1, c) * (1 - tx) + hash(ix + 1, iy + 1, c) * tx;
        image.At(x, y)[c] = 0.15f + 0.7f * (top * (1 - ty) + bottom * ty);
      }
    }
  WritePng(file, image);
}

BenchScene Synthesise(BenchScene scene, const fs::path& dir, const fs::path& scene_file,
                      const fs::path& at_file, const std::vector<SceneOverride>& overrides, double scale,
                      vk::Device& device, int synth_atlas) {
  SynthOptions synth;
  synth.scene_file = scene_file;
  synth.overrides = overrides;
  synth.at_file = at_file;
  synth.output_dir = dir / "images";
  synth.scale = scale;
  synth.atlas = synth_atlas;
  const SynthSummary summary = SynthesiseImages(synth, device);
  scene.scene_file = scene_file;
  scene.at_file = at_file;
  scene.overrides = overrides;
  scene.overrides.push_back({"cameras", summary.cameras_file.string()});
  scene.overrides.push_back({"images", synth.output_dir.string()});
  return scene;
}

}  // namespace

int CylinderTriangles(int requested) {
  const auto [segments, rings] = CylinderTessellation(requested);
  return 2 * segments * rings;
}

BenchScene MakeSyntheticScene(const SyntheticSceneSpec& spec, const fs::path& dir, vk::Device& device) {
  fs::create_directories(dir);
  BenchScene out;
  out.cameras = spec.cameras;
  out.width = spec.width;
  out.height = spec.height;
  out.atlas = spec.atlas;
  MeshData mesh;
  std::vector<Camera> cameras;
  switch (spec.shape) {
    case SyntheticSceneSpec::Shape::Cylinder: {
      const auto [segments, rings] = CylinderTessellation(spec.triangles);
      mesh = Cylinder(segments, rings);
      for (int k = 0; k < spec.cameras; ++k) {
        const double a = 2.0 * M_PI * (k + 0.25) / spec.cameras;
        cameras.push_back(LookAt(CameraName(k), Vector3d(3.0 * std::cos(a), 3.0 * std::sin(a), 1.7),
                                 Vector3d(0, 0, 0.5), spec.width, spec.height));
      }
      break;
    }
    case SyntheticSceneSpec::Shape::BackFacingGrid: {
      mesh = Grid(32, spec.share, &out.backfacing_triangles);
      for (int k = 0; k < spec.cameras; ++k) {
        const double a = 2.0 * M_PI * (k + 0.25) / spec.cameras;
        cameras.push_back(LookAt(CameraName(k), Vector3d(2.5 * std::cos(a), 2.5 * std::sin(a), 2.0),
                                 Vector3d(0, 0, 0), spec.width, spec.height));
      }
      break;
    }
    case SyntheticSceneSpec::Shape::NearClipStrips: {
      int long_strips = 0;
      mesh = Strips(256, spec.share, &long_strips);
      out.clipped_triangles = 2 * long_strips;
      const double pitch = 20.0 * M_PI / 180.0;
      for (int k = 0; k < spec.cameras; ++k) {
        const double x = spec.cameras == 1 ? 0.0 : -1.0 + 2.0 * k / (spec.cameras - 1);
        const Vector3d eye(x, -3.0, 1.2);
        cameras.push_back(LookAt(CameraName(k), eye, eye + Vector3d(0, std::cos(pitch), -std::sin(pitch)),
                                 spec.width, spec.height));
      }
      break;
    }
  }
  out.triangles = int(mesh.indices.size() / 3);
  WriteGltf(mesh, dir, "mesh");
  WriteTexture(dir / "texture.png");
  WriteCamerasJson(dir / "cameras.json", cameras);

  using J = nlohmann::ordered_json;
  J scene;
  scene["version"] = 1;
  scene["images"] = "images/";
  scene["cameras"] = "cameras.json";
  scene["parameters"] = {{"x", {{"prior", {{"uniform", {-0.2, 0.2}}}}, {"init", 0.0}}}};
  scene["nodes"] = J::array({{{"name", "object"}, {"primitive", {{"mesh", "mesh.gltf"}}}, {"albedo", "texture.png"},
                              {"transforms", J::array({{{"translate", {"x", 0, 0}}}})}}});
  scene["likelihood"] = {{"kind", "surface"}, {"sigma", 8.0}, {"weights", "angle"}, {"atlas", spec.atlas},
                         {"levels", spec.levels}};
  scene["sampler"] = {{"batch", 16}};
  WriteJson(dir / "scene.json", scene);
  WriteJson(dir / "at.json", J{{"x", 0.0}});
  // The synthetic scenes' albedo is smooth noise: a 1024² truth atlas is plenty and bakes fast.
  return Synthesise(out, dir, dir / "scene.json", dir / "at.json", {}, 1.0, device, 1024);
}

BenchScene PrepareAsset(const fs::path& asset_dir, const fs::path& dir, double scale, int max_cameras,
                        int atlas, vk::Device& device) {
  fs::create_directories(dir);
  const fs::path scene_file = fs::absolute(asset_dir / "scene.json");
  std::vector<SceneOverride> overrides;
  if (atlas > 0) overrides.push_back({"likelihood.atlas", std::to_string(atlas)});
  LoadOptions load;
  load.require_images = false;
  Scene scene = LoadScene(scene_file, overrides, load);
  if (max_cameras > 0 && int(scene.cameras.size()) > max_cameras) {
    // The first cameras of the asset, written as a camera file of their own.
    std::vector<Camera> kept = scene.Cameras(scene.InitialValues());
    kept.resize(size_t(max_cameras));
    WriteCamerasJson(dir / "cameras_in.json", kept);
    overrides.push_back({"cameras", (dir / "cameras_in.json").string()});
    scene = LoadScene(scene_file, overrides, load);
  }
  ResolveAutoLikelihood(scene);
  BenchScene out;
  out.cameras = int(scene.cameras.size());
  const LikelihoodSettings settings = LikelihoodSettingsOf(scene);
  out.atlas = settings.atlas;
  out.width = std::max(1, int(std::lround(scene.cameras.at(0).width * scale)));
  out.height = std::max(1, int(std::lround(scene.cameras.at(0).height * scale)));
  out.triangles = int(BuildSceneGeometry(scene, scene.InitialValues(), out.atlas, settings.charts).indices.size() / 3);
  return Synthesise(out, dir, scene_file, fs::absolute(asset_dir / "truth.json"), overrides, scale, device, 2048);
}

}  // namespace vkr
