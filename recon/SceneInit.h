#pragma once
// `vkrecon init`: a COLMAP sparse model → a scene folder in a Z-up frame with a starter scene
// (docs/guide/REAL_PHOTOS.md). The ground is a plane fitted to the triangulated points (GroundPlane.h)
// and put at z = 0, the origin under the robust centre of the points above it, +x along the
// principal axis of their footprint; the cameras, the points and a template's priors follow.

#include <Eigen/Core>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace vkr::recon {

// The starter scenes `init` writes: a box on the ground (x y yaw w d h, as assets/box), a
// house, walls box + roof prism (x y yaw w d h rh, as assets/house), a standing cylinder
// (x y diameter height, as assets/poster), four steps (x y yaw width run rise, as
// assets/stairs, StairsFit.h), or two walls meeting in an inside corner that the cameras look
// into (xc yc yaw angle h, CornerFit.h).
enum class InitTemplate { Box, House, Cylinder, Stairs, Corner };
const char* ToString(InitTemplate t);
bool FromString(const std::string& text, InitTemplate* t);

// One known length: the distance between two triangulated points (POINT3D_IDs) in metres.
struct ScalePoints {
  std::uint64_t a = 0, b = 0;
  double length = 0.0;
};
// Parses "ID1,ID2=LENGTH"; InputError("", "--scale-points", …) otherwise.
ScalePoints ParseScalePoints(const std::string& text);

struct InitOptions {
  std::filesystem::path sparse;  // the COLMAP model's folder (binary or text)
  std::filesystem::path output;  // the scene folder to write (created; no scene.json in it yet)
  // The photographs COLMAP's NAMEs are relative to; empty: SPARSE/../images, or, for COLMAP's
  // SPARSE = project/sparse/0, project/images.
  std::filesystem::path images;
  InitTemplate template_kind = InitTemplate::Box;
  // Up in the model's frame; none: the cameras' mean up (COLMAP's image y points down).
  std::optional<Eigen::Vector3d> up;
  // Metres from one known length; none: the scene keeps COLMAP's units.
  std::optional<ScalePoints> scale;
  // The ground's inlier distance as a share of the cloud's size (the median distance of the
  // points from their median).
  double ground_tolerance = 0.02;
  std::uint64_t seed = 1;  // RANSAC's
  // The starter scene's `max_side` when a photograph is larger (0: none): phone photographs
  // go in shrunk by an integer factor instead of at 12 megapixels (engine/scene/Photographs.h).
  int max_side = 1600;
};

// What init found and wrote; BriefReport() is what the command prints.
struct InitResult {
  int images_count = 0;    // registered images
  int points = 0;          // read from points3D
  int ground_inliers = 0;  // on the fitted ground
  int above = 0;           // above it near what the cameras look at: what sets the priors
  Eigen::Vector3d up = Eigen::Vector3d::UnitZ();  // the ground's normal, model frame
  double up_vs_cameras_deg = 0.0;  // its angle to the cameras' mean up
  double scale = 1.0;              // scene units per model unit
  bool metres = false;             // whether `scale` came from a known length
  // X_scene = scene_from_model · X_model (a similarity: scale · rotation, translation).
  Eigen::Matrix4d scene_from_model = Eigen::Matrix4d::Identity();
  // Robust box of those points (2nd to 98th percentiles), scene frame.
  Eigen::Vector3d lo = Eigen::Vector3d::Zero(), hi = Eigen::Vector3d::Zero();
  std::filesystem::path images;  // the photographs' folder
  std::optional<std::filesystem::path> masks;  // the masks' folder, when there is one
  int largest_side = 0;  // of the photographs
  int max_side = 0;      // written to the scene (0: none, the photographs are used as they are)
  std::vector<std::filesystem::path> written;
  std::string BriefReport() const;
};

// Reads the model, fits the ground, writes OUTPUT/cameras.json, points.ply (ASCII, with
// colours, scene frame), scene.json (the template) and init.json (the effective options and
// the similarity). Throws InputError for bad input: a model without points or with one image,
// no ground, a template the points do not fit, a photograph missing, a scene.json in OUTPUT.
InitResult InitScene(const InitOptions& options);

}  // namespace vkr::recon
