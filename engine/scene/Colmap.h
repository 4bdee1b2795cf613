#pragma once
// COLMAP's text model (cameras.txt + images.txt, as written by `colmap model_converter
// --output_type TXT`): one vkrecon camera per registered image (DESIGN.md, "cameras").

#include <Eigen/Core>
#include <filesystem>
#include <string>
#include <vector>

namespace vkr {

// One registered image of a COLMAP model, in vkrecon's (and COLMAP's) convention:
// x_cam = R·X + t, pixel centres at +0.5, so no conversion is needed.
struct ColmapImage {
  std::string name;   // NAME without folders and extension: the camera's name
  std::string image;  // NAME as written, relative to the images folder
  int width = 0, height = 0;
  double fx = 0, fy = 0, cx = 0, cy = 0;
  Eigen::Matrix3d R = Eigen::Matrix3d::Identity();  // from the normalised quaternion
  Eigen::Vector3d t = Eigen::Vector3d::Zero();
};

// Reads `dir`/cameras.txt and `dir`/images.txt, in the order of images.txt. Only the
// PINHOLE (fx fy cx cy) and SIMPLE_PINHOLE (f cx cy) models are accepted: vkrecon renders
// without lens distortion. Throws InputError(file, "line N", problem) naming the text file
// (shown as `display_dir`/…).
std::vector<ColmapImage> ReadColmapText(const std::filesystem::path& dir,
                                        const std::string& display_dir);

}  // namespace vkr
