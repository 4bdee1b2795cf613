// The report's wireframe overlay (pipelines/rendering/WireframeOverlay.h) lands where the
// model is: on photographs of the box at its truth, the pixels the overlay changes lie on the
// box as the GPU renders it, and they trace its whole outline — through a pinhole and
// through a distorting lens. The rasteriser is the independent reference. With the camera's
// depth buffer (HiddenLines.h) the box's far edges, which its faces hide, are left out.

#include <gtest/gtest.h>

#include <algorithm>
#include <nlohmann/json.hpp>

#include "engine/scene/LensDistortion.h"
#include "pipelines/rendering/ViewRendering.h"
#include "pipelines/rendering/WireframeOverlay.h"
#include "tests/common/GpuTest.h"
#include "tests/common/TestFiles.h"

namespace vkr {
namespace {

namespace fs = std::filesystem;
const fs::path kBox = fs::path(VKRECON_SOURCE_DIR) / "assets/box";

// Whether some pixel within `radius` (Chebyshev) of (x, y) satisfies `mask`.
bool Near(const std::vector<char>& mask, int w, int h, int x, int y, int radius) {
  for (int dy = -radius; dy <= radius; ++dy)
    for (int dx = -radius; dx <= radius; ++dx) {
      const int u = x + dx, v = y + dy;
      if (u >= 0 && v >= 0 && u < w && v < h && mask[size_t(v) * w + u]) return true;
    }
  return false;
}

// `hidden`: draw with each camera's depth buffer, and check that the edges between two faces
// turned away from the camera (hidden on a closed box) leave the photograph as it was.
// Points a fifth to four fifths along each edge between two faces turned away from `camera`,
// away from every other edge's projection: unchanged in `overlay`, drawn without hiding.
void ExpectHiddenEdgesLeftOut(const Image& photo, const Image& overlay, const Camera& camera,
                              const std::vector<WireEdge>& edges) {
  const Eigen::Vector3d centre = camera.Centre();
  const auto pixel = [&](const Eigen::Vector3d& world) {
    return LensPixel(camera, (camera.cam_from_world * world.homogeneous()).head<3>());
  };
  const Image unhidden = DrawWireframe(photo, camera, edges);
  int probed = 0, drawn_unhidden = 0, drawn = 0;
  for (const WireEdge& e : edges) {
    const Eigen::Vector3d view = centre - 0.5 * (e.a + e.b);
    if (!IsDrawnEdge(e, centre)) continue;                                          // a face's diagonal
    if (e.normals[0].dot(view) > 0.0 || e.normals[1].dot(view) > 0.0) continue;  // not a hidden edge
    for (double t = 0.2; t <= 0.8; t += 0.05) {
      const Eigen::Vector2d p = pixel(e.a + t * (e.b - e.a));
      bool clear = true;  // no other drawn edge within 4 pixels
      for (const WireEdge& other : edges) {
        if (&other == &e || !IsDrawnEdge(other, centre)) continue;
        const Eigen::Vector2d a = pixel(other.a), b = pixel(other.b);
        const double u = std::clamp((p - a).dot(b - a) / std::max((b - a).squaredNorm(), 1e-12), 0.0, 1.0);
        clear = clear && (a + u * (b - a) - p).norm() > 4.0;
      }
      const int x = int(p.x()), y = int(p.y());
      if (!clear || x < 0 || y < 0 || x >= photo.width || y >= photo.height) continue;
      ++probed;
      const auto changed = [&](const Image& image) {  // some pixel within one of the point
        float d = 0.0f;
        for (int v = std::max(y - 1, 0); v <= std::min(y + 1, photo.height - 1); ++v)
          for (int u = std::max(x - 1, 0); u <= std::min(x + 1, photo.width - 1); ++u)
            for (int c = 0; c < 3; ++c) d = std::max(d, std::abs(image.At(u, v)[c] - photo.At(u, v)[c]));
        return d > 0.1f;
      };
      drawn_unhidden += changed(unhidden);
      drawn += changed(overlay);
    }
  }
  EXPECT_GT(probed, 5) << camera.name << ": no hidden edge to look at";
  EXPECT_GE(drawn_unhidden, probed * 9 / 10) << camera.name << ": without the depth buffer they are drawn";
  EXPECT_EQ(drawn, 0) << camera.name << ": an edge the box hides was drawn";
}

void ExpectWireframeOnTheBox(vk::Device& device, const std::optional<LensDistortion>& lens, bool hidden = false) {
  test::TempDir dir;
  SynthOptions synth;
  synth.scene_file = kBox / "scene.json";
  synth.at_file = kBox / "truth.json";
  synth.output_dir = dir / "images";
  synth.scale = 0.25;
  synth.atlas = 256;
  synth.distortion = lens;
  SynthesiseImages(synth, device);
  // The box alone (its ground left out), so the rendered coverage is the box's silhouette.
  const nlohmann::json file = nlohmann::json::parse(test::ReadText(kBox / "scene.json"));
  const nlohmann::json box_only = nlohmann::json::array({file["nodes"][1]});
  ASSERT_EQ(box_only[0]["name"], "box");
  const Scene scene = LoadScene(kBox / "scene.json", {{"cameras", (dir / "images/cameras.json").string()},
                                                      {"images", (dir / "images").string()},
                                                      {"nodes", box_only.dump()}});
  const std::vector<double> truth = scene.ValuesFromFile(kBox / "truth.json");
  const SceneGeometry geometry = BuildSceneGeometry(scene, truth, 64, ChartSizing::Area);

  // A closed box: 12 edges and 6 face diagonals, each between two triangles; the 12 are creases.
  const std::vector<WireEdge> edges = SceneEdges(scene, geometry, truth);
  ASSERT_EQ(edges.size(), 18u);
  int creases = 0;
  for (const WireEdge& e : edges) {
    ASSERT_EQ(e.normals.size(), 2u);
    creases += e.normals[0].dot(e.normals[1]) < 0.5;
  }
  EXPECT_EQ(creases, 12);

  const std::vector<Camera> cameras = scene.Cameras(truth);
  const std::vector<Image> rendered =
      RenderWithAtlas(device, scene, truth, geometry, Image(geometry.atlas.size, geometry.atlas.size, 1.0f), cameras);
  const std::vector<WorldTriangle> triangles = SceneTriangles(scene, geometry, truth);
  ASSERT_EQ(triangles.size(), 12u);
  for (size_t i = 0; i < cameras.size(); ++i) {
    const Image photo = LoadImage(cameras[i].image);
    const DepthBuffer depth(cameras[i], triangles);
    const Image overlay = DrawWireframe(photo, cameras[i], edges, {}, hidden ? &depth : nullptr);
    if (hidden) ExpectHiddenEdgesLeftOut(photo, overlay, cameras[i], edges);
    const int w = photo.width, h = photo.height;
    std::vector<char> changed(size_t(w) * h), covered(size_t(w) * h);
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        float d = 0.0f;
        for (int c = 0; c < 3; ++c) d = std::max(d, std::abs(overlay.At(x, y)[c] - photo.At(x, y)[c]));
        changed[size_t(y) * w + x] = d > 0.1f;
        covered[size_t(y) * w + x] = rendered[i].At(x, y)[3] > 0.0f;
      }
    int drawn = 0, off_model = 0, outline = 0, traced = 0;
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        if (changed[size_t(y) * w + x]) {
          ++drawn;
          off_model += !Near(covered, w, h, x, y, 1);
        }
        // The silhouette: covered pixels beside an uncovered one, away from the border.
        if (!covered[size_t(y) * w + x] || x == 0 || y == 0 || x == w - 1 || y == h - 1) continue;
        if (covered[size_t(y) * w + x - 1] && covered[size_t(y) * w + x + 1] && covered[size_t(y - 1) * w + x] &&
            covered[size_t(y + 1) * w + x])
          continue;
        ++outline;
        traced += Near(changed, w, h, x, y, 1);
      }
    SCOPED_TRACE(cameras[i].name);
    ASSERT_GT(outline, 40) << "the box should fill a fair part of the image";
    EXPECT_GT(drawn, outline / 2);
    EXPECT_LE(off_model, drawn / 300) << "the wireframe strays off the rendered box";
    EXPECT_GE(traced, outline * 99 / 100) << "the wireframe misses part of the box's outline";
  }
}

class WireframeOverlay : public test::GpuTest {};

TEST_F(WireframeOverlay, TracesTheRenderedBox) { ExpectWireframeOnTheBox(device(), std::nullopt); }

TEST_F(WireframeOverlay, LeavesOutTheEdgesTheBoxHides) { ExpectWireframeOnTheBox(device(), std::nullopt, true); }

TEST_F(WireframeOverlay, LeavesOutTheEdgesTheBoxHidesThroughALens) {
  ExpectWireframeOnTheBox(device(), ParseDistortionSpec("OPENCV:k1=-0.6,k2=0.2", "--lens"), true);
}

// Strong enough that leaving the lens out moves the lines off the box by a pixel or more.
TEST_F(WireframeOverlay, TracesTheRenderedBoxThroughALens) {
  ExpectWireframeOnTheBox(device(), ParseDistortionSpec("OPENCV:k1=-0.6,k2=0.2", "--lens"));
}

}  // namespace
}  // namespace vkr
