#pragma once
// COLMAP's sparse model, text (cameras.txt, images.txt, points3D.txt, as written by `colmap
// model_converter --output_type TXT`) and binary (cameras.bin, images.bin, points3D.bin, what
// `colmap mapper` writes): one vkrecon camera per registered image (docs/guide/SCENE_FORMAT.md, "cameras"),
// and the triangulated points that `vkrecon init` places the ground and the priors by.

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "engine/scene/LensDistortion.h"

namespace vkr {

struct Camera;

// One registered image of a COLMAP model, in vkrecon's (and COLMAP's) convention:
// x_cam = R·X + t, pixel centres at +0.5, so no conversion is needed.
struct ColmapImage {
  std::string name;   // NAME without folders and extension: the camera's name
  std::string image;  // NAME as written, relative to the images folder
  int width = 0, height = 0;
  double fx = 0, fy = 0, cx = 0, cy = 0;
  LensDistortion distortion;  // None for PINHOLE and SIMPLE_PINHOLE
  Eigen::Matrix3d R = Eigen::Matrix3d::Identity();  // from the normalised quaternion
  Eigen::Vector3d t = Eigen::Vector3d::Zero();
};

// One triangulated point of points3D.txt / points3D.bin, in the model's (world) frame.
struct ColmapPoint {
  std::uint64_t id = 0;  // POINT3D_ID
  Eigen::Vector3d xyz = Eigen::Vector3d::Zero();
  std::array<std::uint8_t, 3> rgb{};
  double error = 0.0;  // mean reprojection error, pixels
  std::vector<std::pair<std::uint32_t, std::uint32_t>> track;  // (IMAGE_ID, POINT2D_IDX)
};

// A whole sparse model: the registered images (in file order) and the points.
struct ColmapReconstruction {
  std::vector<ColmapImage> images;
  std::vector<ColmapPoint> points;
};

// Reads `dir`/cameras.txt and `dir`/images.txt, in the order of images.txt. Accepted
// models: SIMPLE_PINHOLE (f cx cy), PINHOLE (fx fy cx cy), SIMPLE_RADIAL (f cx cy k),
// RADIAL (f cx cy k1 k2), OPENCV (fx fy cx cy k1 k2 p1 p2) and FULL_OPENCV (fx fy cx cy
// k1 k2 p1 p2 k3 k4 k5 k6); the distortion models' coefficients are LensDistortion.h's.
// Any other model (the fisheyes, FOV, …) is refused by name. Throws InputError(file,
// "line N", problem) naming the text file (shown as `display_dir`/…).
std::vector<ColmapImage> ReadColmapText(const std::filesystem::path& dir,
                                        const std::string& display_dir);

// Reads `file` (points3D.txt): "POINT3D_ID X Y Z R G B ERROR TRACK[]" lines. Throws
// InputError(file shown as `display`, "line N", problem).
std::vector<ColmapPoint> ReadColmapPointsText(const std::filesystem::path& file,
                                              const std::string& display);

// Reads the binary model of `dir` (cameras.bin, images.bin, points3D.bin) in COLMAP's
// little-endian layout, accepting the models ReadColmapText accepts. A file that ends inside a
// record, or holds bytes after the last one, is refused: InputError(`display_dir`/file,
// "camera|image|point N" (the record's place, from 1), problem).
ColmapReconstruction ReadColmapBinary(const std::filesystem::path& dir, const std::string& display_dir);

// The model of `dir`: binary when `dir`/cameras.bin exists (as COLMAP decides), else text.
// A missing points3D file is an error (InputError naming it).
ColmapReconstruction ReadColmapModel(const std::filesystem::path& dir, const std::string& display_dir);

// Writes `model` as a binary model in `dir`, IMAGE_ID i+1 and CAMERA_ID i+1 for images[i],
// each camera with the COLMAP model its lens came from (PINHOLE for none), no 2D points.
void WriteColmapBinary(const std::filesystem::path& dir, const ColmapReconstruction& model);

// Writes `cameras` as a COLMAP text model in `dir` (cameras.txt, images.txt and points3D.txt
// with `points`, empty by default), one COLMAP camera per image: PINHOLE without distortion, FULL_OPENCV for
// FULL_OPENCV, OPENCV for the others (SIMPLE_RADIAL's k and RADIAL's k1 k2 are OPENCV's k1
// k2 with the rest 0, so nothing changes). NAME is each image relative to `images_dir`.
// Throws InputError for a camera COLMAP cannot describe (skew in K).
void WriteColmapText(const std::filesystem::path& dir, const std::vector<Camera>& cameras,
                     const std::filesystem::path& images_dir,
                     const std::vector<ColmapPoint>& points = {});

}  // namespace vkr
