#include "pipelines/rendering/ModelExport.h"

#include <tiny_gltf.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>

#include "engine/common/InputError.h"
#include "engine/image/ChiSquareRamp.h"
#include "engine/image/Pyramid.h"
#include "engine/scene/Photographs.h"
#include "pipelines/rendering/ViewRendering.h"

namespace fs = std::filesystem;

namespace vkr {
namespace {

// Appends raw bytes to the model's single buffer and returns a buffer view over them.
int AddBufferView(tinygltf::Model& model, const void* data, size_t bytes, int target) {
  std::vector<unsigned char>& buffer = model.buffers[0].data;
  while (buffer.size() % 4) buffer.push_back(0);  // accessors need 4-byte alignment
  tinygltf::BufferView view;
  view.buffer = 0;
  view.byteOffset = buffer.size();
  view.byteLength = bytes;
  view.target = target;
  const auto* p = static_cast<const unsigned char*>(data);
  buffer.insert(buffer.end(), p, p + bytes);
  model.bufferViews.push_back(view);
  return int(model.bufferViews.size()) - 1;
}

int AddAccessor(tinygltf::Model& model, int view, int component, int type, size_t count,
                std::vector<double> min = {}, std::vector<double> max = {}) {
  tinygltf::Accessor a;
  a.bufferView = view;
  a.componentType = component;
  a.type = type;
  a.count = count;
  a.minValues = std::move(min);
  a.maxValues = std::move(max);
  model.accessors.push_back(a);
  return int(model.accessors.size()) - 1;
}

}  // namespace

Image DilateAtlas(const Image& atlas, int iterations) {
  Image out = atlas;
  for (size_t i = 3; i < out.rgba.size(); i += 4) out.rgba[i] = out.rgba[i] > 0.0f ? 1.0f : 0.0f;
  for (int it = 0; it < iterations; ++it) {
    Image next = out;
    for (int y = 0; y < out.height; ++y)
      for (int x = 0; x < out.width; ++x) {
        if (out.At(x, y)[3] > 0.0f) continue;
        float sum[3] = {0, 0, 0};
        int n = 0;
        const int dx[] = {1, -1, 0, 0}, dy[] = {0, 0, 1, -1};
        for (int k = 0; k < 4; ++k) {
          const int u = x + dx[k], v = y + dy[k];
          if (u < 0 || v < 0 || u >= out.width || v >= out.height || out.At(u, v)[3] == 0.0f) continue;
          for (int c = 0; c < 3; ++c) sum[c] += out.At(u, v)[c];
          ++n;
        }
        if (n == 0) continue;
        float* p = next.At(x, y);
        for (int c = 0; c < 3; ++c) p[c] = sum[c] / n;
        p[3] = 1.0f;
      }
    out = std::move(next);
  }
  return out;
}

void WriteTexturedGlb(const fs::path& file, const Scene& scene, const SceneGeometry& geometry,
                      const std::vector<double>& psi, const Image& atlas) {
  tinygltf::Model model;
  model.asset.version = "2.0";
  model.asset.generator = "vkrecon";
  model.buffers.resize(1);
  model.extensionsUsed.push_back("KHR_materials_unlit");

  tinygltf::Image image;
  image.width = atlas.width;
  image.height = atlas.height;
  image.component = 4;
  image.bits = 8;
  image.pixel_type = TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE;
  image.mimeType = "image/png";
  image.image.resize(atlas.rgba.size());
  for (size_t i = 0; i < atlas.rgba.size(); ++i)
    image.image[i] = (i % 4 == 3) ? 255 : uint8_t(std::lround(std::clamp(atlas.rgba[i], 0.0f, 1.0f) * 255.0f));
  model.images.push_back(image);
  tinygltf::Sampler sampler;
  sampler.magFilter = TINYGLTF_TEXTURE_FILTER_LINEAR;
  sampler.minFilter = TINYGLTF_TEXTURE_FILTER_LINEAR;
  sampler.wrapS = sampler.wrapT = TINYGLTF_TEXTURE_WRAP_CLAMP_TO_EDGE;
  model.samplers.push_back(sampler);
  tinygltf::Texture texture;
  texture.sampler = 0;
  texture.source = 0;
  model.textures.push_back(texture);
  tinygltf::Material material;
  material.name = "composite";
  material.pbrMetallicRoughness.baseColorTexture.index = 0;
  material.pbrMetallicRoughness.metallicFactor = 0.0;
  material.pbrMetallicRoughness.roughnessFactor = 1.0;
  material.doubleSided = true;
  material.extensions["KHR_materials_unlit"] = tinygltf::Value(tinygltf::Value::Object());
  model.materials.push_back(material);

  const std::vector<Eigen::Matrix4d> world_from_node = scene.WorldFromNode(psi);
  tinygltf::Scene gscene;
  // Vertices and indices of a node are contiguous in the flattened geometry.
  for (size_t node = 0; node < scene.nodes.size(); ++node) {
    std::vector<float> positions, normals, uvs;
    std::vector<uint32_t> indices;
    std::vector<int> remap(geometry.vertices.size(), -1);
    const Eigen::Matrix4d& m = world_from_node[node];
    const Eigen::Matrix3d normal_matrix = m.topLeftCorner<3, 3>().inverse().transpose();
    Eigen::Vector3d lo = Eigen::Vector3d::Constant(1e300), hi = -lo;
    for (uint32_t index : geometry.indices) {
      const GpuVertex& v = geometry.vertices[index];
      if (v.node != node) continue;
      if (remap[index] < 0) {
        remap[index] = int(positions.size() / 3);
        const Eigen::Vector3d w = (m * Eigen::Vector4d(v.position[0], v.position[1], v.position[2], 1.0)).head<3>();
        const Eigen::Vector3d n = (normal_matrix * Eigen::Vector3d(v.normal[0], v.normal[1], v.normal[2])).normalized();
        const Eigen::Vector3d y_up(w.x(), w.z(), -w.y());  // Z-up → glTF's Y-up
        lo = lo.cwiseMin(y_up);
        hi = hi.cwiseMax(y_up);
        for (int k = 0; k < 3; ++k) positions.push_back(float(y_up[k]));
        normals.insert(normals.end(), {float(n.x()), float(n.z()), float(-n.y())});
        uvs.insert(uvs.end(), {v.atlas_uv[0], v.atlas_uv[1]});
      }
      indices.push_back(uint32_t(remap[index]));
    }
    if (indices.empty()) continue;
    const size_t count = positions.size() / 3;
    tinygltf::Primitive prim;
    prim.mode = TINYGLTF_MODE_TRIANGLES;
    prim.material = 0;
    prim.attributes["POSITION"] = AddAccessor(
        model, AddBufferView(model, positions.data(), positions.size() * 4, TINYGLTF_TARGET_ARRAY_BUFFER),
        TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC3, count, {lo.x(), lo.y(), lo.z()}, {hi.x(), hi.y(), hi.z()});
    prim.attributes["NORMAL"] = AddAccessor(
        model, AddBufferView(model, normals.data(), normals.size() * 4, TINYGLTF_TARGET_ARRAY_BUFFER),
        TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC3, count);
    prim.attributes["TEXCOORD_0"] = AddAccessor(
        model, AddBufferView(model, uvs.data(), uvs.size() * 4, TINYGLTF_TARGET_ARRAY_BUFFER),
        TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC2, count);
    prim.indices = AddAccessor(
        model, AddBufferView(model, indices.data(), indices.size() * 4, TINYGLTF_TARGET_ELEMENT_ARRAY_BUFFER),
        TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT, TINYGLTF_TYPE_SCALAR, indices.size());
    tinygltf::Mesh mesh;
    mesh.name = scene.nodes[node].name;
    mesh.primitives.push_back(prim);
    model.meshes.push_back(mesh);
    tinygltf::Node gnode;
    gnode.name = scene.nodes[node].name;
    gnode.mesh = int(model.meshes.size()) - 1;
    model.nodes.push_back(gnode);
    gscene.nodes.push_back(int(model.nodes.size()) - 1);
  }
  model.scenes.push_back(gscene);
  model.defaultScene = 0;
  tinygltf::TinyGLTF writer;
  if (!writer.WriteGltfSceneToFile(&model, file.string(), /*embedImages=*/true, /*embedBuffers=*/true,
                                   /*prettyPrint=*/false, /*writeBinary=*/true))
    throw InputError(file.string(), "", "cannot write the glTF model");
}

std::vector<Reprojection> WriteReprojections(const fs::path& dir, vk::Device& device, const Scene& scene,
                                             const SceneGeometry& geometry, const std::vector<double>& psi,
                                             const Image& atlas, const ReprojectionNoise& noise) {
  fs::create_directories(dir);
  const std::vector<Camera> cameras = scene.Cameras(psi);
  const std::vector<Image> synthetic = RenderWithAtlas(device, scene, psi, geometry, atlas, cameras);
  const double sigma2 = std::pow(noise.sigma_255 / 255.0, 2), delta2 = noise.position_sd * noise.position_sd;
  std::vector<Reprojection> written;
  for (size_t i = 0; i < cameras.size(); ++i) {
    Image reference = LoadPhotograph(cameras[i].image, cameras[i].shrink);
    const int w = reference.width, h = reference.height;
    Image strip(3 * w, h, 0.0f), residual(w, h, 0.0f);
    Image gradient = reference;
    StoreGradientInAlpha(gradient);  // the noise model's |∇I|
    std::array<double, 3> gain{1, 1, 1}, offset{0, 0, 0};
    if (i < size_t(noise.photometric.cameras())) gain = noise.photometric.gain[i], offset = noise.photometric.offset[i];
    Reprojection out;
    out.camera = cameras[i].name;
    double squares = 0.0;
    int64_t outliers = 0;
    // Per pixel, the residual's χ² per channel under the noise model, −1 where the model does
    // not reach or clutter was masked.
    std::vector<double> chi2(size_t(w) * h, -1.0);
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        const float* r = reference.At(x, y);
        const float* s = synthetic[i].At(x, y);
        const bool covered = s[3] > 0.0f;
        double e2 = 0.0;
        for (int c = 0; c < 3; ++c) {
          // The composite is in the cameras' common colours: back to this photograph's.
          const float sc = covered ? float((s[c] - offset[size_t(c)]) / gain[size_t(c)]) : 0.0f;
          const double d = double(r[c]) - sc;
          strip.At(x, y)[c] = r[c];
          strip.At(w + x, y)[c] = sc;
          strip.At(2 * w + x, y)[c] = covered ? std::min(1.0f, 4.0f * float(std::abs(d))) : 0.0f;
          if (covered) e2 += d * d;
        }
        const double g = gradient.At(x, y)[3];
        const bool clutter = i < noise.clutter.size() && noise.clutter[i].At(x, y)[0] < 0.5f;
        float* o = residual.At(x, y);
        if (covered && clutter) {
          const float grey = (r[0] + r[1] + r[2]) / 3.0f;
          o[0] = o[2] = 0.5f + 0.4f * grey;
          o[1] = 0.2f * grey;
        } else if (covered) {  // masked clutter is not evidence: out of the figures
          ++out.pixels;
          squares += e2;
          chi2[size_t(y) * w + x] = e2 / (3.0 * (sigma2 + delta2 * g * g));
        } else {
          for (int c = 0; c < 3; ++c) o[c] = 0.25f * r[c];
        }
        o[3] = 1.0f;
        strip.At(x, y)[3] = strip.At(w + x, y)[3] = strip.At(2 * w + x, y)[3] = 1.0f;
      }
    // A pixel of the model textured with the atlas is blurrier than the photograph, which
    // σ (the noise of the samples the likelihood compares) does not describe: the scale is
    // this photograph's own robust one (its median χ² per channel is χ²₃'s, 0.789), so the
    // image shows where the residuals stand out, not how blurry the atlas is.
    std::vector<double> covered_chi2;
    for (double v : chi2)
      if (v >= 0.0) covered_chi2.push_back(v);
    double scale = 1.0;
    if (!covered_chi2.empty()) {
      std::nth_element(covered_chi2.begin(), covered_chi2.begin() + covered_chi2.size() / 2, covered_chi2.end());
      scale = std::max(covered_chi2[covered_chi2.size() / 2] / 0.789, 1.0);
    }
    for (size_t p = 0; p < chi2.size(); ++p)
      if (chi2[p] >= 0.0) outliers += chi2[p] / scale > 9.0;
    // The image shows the mean over 3×3 pixels, so that regions stand out of the noise's
    // speckle (single pixels of χ²₃ spread from 0.2 to 2 and more).
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        if (chi2[size_t(y) * w + x] < 0.0) continue;
        double sum = 0.0;
        int count = 0;
        for (int dy = -1; dy <= 1; ++dy)
          for (int dx = -1; dx <= 1; ++dx) {
            const int xx = x + dx, yy = y + dy;
            if (xx < 0 || yy < 0 || xx >= w || yy >= h || chi2[size_t(yy) * w + xx] < 0.0) continue;
            sum += chi2[size_t(yy) * w + xx];
            ++count;
          }
        ChiSquareRamp(sum / count / scale, residual.At(x, y));
      }
    out.file = dir / (cameras[i].name + ".png");
    WritePng(out.file, strip);
    out.residual_file = dir / (cameras[i].name + "_residual.png");
    WritePng(out.residual_file, residual);
    out.rms_255 = out.pixels ? 255.0 * std::sqrt(squares / (3.0 * double(out.pixels))) : 0.0;
    out.outlier_share = out.pixels ? double(outliers) / double(out.pixels) : 0.0;
    written.push_back(out);
  }
  return written;
}

}  // namespace vkr
