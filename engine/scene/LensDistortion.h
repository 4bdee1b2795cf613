#pragma once
// Lens distortion of real cameras, as OpenCV and COLMAP define it (docs/guide/SCENE_FORMAT.md,
// "Lens distortion"): a map of *normalised* image coordinates (x, y) = (X/Z, Y/Z) of a camera-frame
// point to the distorted normalised coordinates the lens actually images it at; K then maps those
// to pixels. vkrecon renders pinhole cameras, so a photograph taken through a lens is resampled
// once, when it is loaded, to the pinhole image of the same K (pipelines/rendering/LensWarp.h).
//
// Models and their coefficients, named and ordered as COLMAP's cameras.txt lists them
// after the focal lengths and principal point:
//   SIMPLE_RADIAL  k                          radial 1 + k r²
//   RADIAL         k1 k2                      radial 1 + k1 r² + k2 r⁴
//   OPENCV         k1 k2 p1 p2                radial 1 + k1 r² + k2 r⁴, tangential p1 p2
//   FULL_OPENCV    k1 k2 p1 p2 k3 k4 k5 k6    radial (1 + k1 r² + k2 r⁴ + k3 r⁶) /
//                                                    (1 + k4 r² + k5 r⁴ + k6 r⁶), tangential
// with r² = x² + y² and
//   x_d = x·radial + 2 p1 x y + p2 (r² + 2x²),   y_d = y·radial + p1 (r² + 2y²) + 2 p2 x y.
// Every model is the FULL_OPENCV formula with the coefficients it lacks at zero.

#include <Eigen/Core>
#include <array>
#include <string>
#include <vector>

namespace vkr {

enum class DistortionModel { None, SimpleRadial, Radial, OpenCV, FullOpenCV };

// COLMAP's model names ("SIMPLE_RADIAL", …; None is "NONE", which no file may name).
const char* ToString(DistortionModel model);
// False for names that are not one of the four distortion models.
bool FromString(const std::string& name, DistortionModel* model);
// The coefficient names of `model` in COLMAP's order ({} for None).
const std::vector<std::string>& CoefficientNames(DistortionModel model);
// "SIMPLE_RADIAL, RADIAL, OPENCV, FULL_OPENCV", for messages.
std::string DistortionModelList();

struct LensDistortion {
  DistortionModel model = DistortionModel::None;
  // In the order of CoefficientNames(model); the rest stay 0.
  std::array<double, 8> coefficients{};

  bool IsNone() const { return model == DistortionModel::None; }
  // Coefficient by COLMAP name (k, k1, …, p2); std::invalid_argument if the model lacks it.
  double Coefficient(const std::string& name) const;
  // The eight FULL_OPENCV coefficients k1 k2 p1 p2 k3 k4 k5 k6 that give this model (the
  // ones it lacks at zero): one formula serves every model.
  std::array<double, 8> FullOpenCV() const;

  // Distorted normalised coordinates of the undistorted point `x`; `jacobian`, when given,
  // receives ∂x_d/∂x.
  Eigen::Vector2d Distort(const Eigen::Vector2d& x, Eigen::Matrix2d* jacobian = nullptr) const;

  // The undistorted point whose distortion is `distorted`, by Newton's method started at
  // `distorted` itself (so it finds the preimage nearest the lens's centre region, not a
  // fold far outside the image). False when it does not converge to |residual| < 1e-12
  // (≈ 1e-9 px at f = 1000) within 50 steps: such a pixel has no usable ray.
  bool Undistort(const Eigen::Vector2d& distorted, Eigen::Vector2d* undistorted) const;
};

// Parses the command-line form MODEL[:NAME=VALUE[,NAME=VALUE…]], e.g.
// "OPENCV:k1=-0.12,k2=0.03"; coefficients not named are 0. Throws InputError("", `option`,
// problem) for an unknown model or coefficient, a repeated one, or a value that is not a
// finite number.
LensDistortion ParseDistortionSpec(const std::string& spec, const std::string& option);

}  // namespace vkr
