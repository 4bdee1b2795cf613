#pragma once
// COLMAP's text model (cameras.txt + images.txt, as written by `colmap model_converter
// --output_type TXT`): one vkrecon camera per registered image (DESIGN.md, "cameras").

#include <Eigen/Core>
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

// Reads `dir`/cameras.txt and `dir`/images.txt, in the order of images.txt. Accepted
// models: SIMPLE_PINHOLE (f cx cy), PINHOLE (fx fy cx cy), SIMPLE_RADIAL (f cx cy k),
// RADIAL (f cx cy k1 k2), OPENCV (fx fy cx cy k1 k2 p1 p2) and FULL_OPENCV (fx fy cx cy
// k1 k2 p1 p2 k3 k4 k5 k6); the distortion models' coefficients are LensDistortion.h's.
// Any other model (the fisheyes, FOV, …) is refused by name. Throws InputError(file,
// "line N", problem) naming the text file (shown as `display_dir`/…).
std::vector<ColmapImage> ReadColmapText(const std::filesystem::path& dir,
                                        const std::string& display_dir);

// Writes `cameras` as a COLMAP text model in `dir` (cameras.txt, images.txt and an empty
// points3D.txt), one COLMAP camera per image: PINHOLE without distortion, FULL_OPENCV for
// FULL_OPENCV, OPENCV for the others (SIMPLE_RADIAL's k and RADIAL's k1 k2 are OPENCV's k1
// k2 with the rest 0, so nothing changes). NAME is each image relative to `images_dir`.
// Throws InputError for a camera COLMAP cannot describe (skew in K).
void WriteColmapText(const std::filesystem::path& dir, const std::vector<Camera>& cameras,
                     const std::filesystem::path& images_dir);

}  // namespace vkr
