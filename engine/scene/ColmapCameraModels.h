#pragma once
// COLMAP's camera models as vkrecon reads them, shared by the text and the binary readers
// (Colmap.cpp, ColmapBinary.cpp) so that both accept and refuse exactly the same models.

#include <string>
#include <vector>

#include "engine/scene/Colmap.h"
#include "engine/scene/LensDistortion.h"

namespace vkr::colmap_detail {

// One COLMAP camera's size, K and lens.
struct ColmapIntrinsics {
  int width = 0, height = 0;
  double fx = 0, fy = 0, cx = 0, cy = 0;
  LensDistortion distortion;
};

// A COLMAP model vkrecon reads: COLMAP's model id (cameras.bin), its name (cameras.txt),
// whether it has one focal length (f) or two (fx fy), and its distortion (None: pinhole).
struct ColmapCameraModel {
  int id;
  const char* name;
  bool single_focal;
  DistortionModel distortion;
};
inline constexpr ColmapCameraModel kColmapCameraModels[] = {
    {0, "SIMPLE_PINHOLE", true, DistortionModel::None},
    {1, "PINHOLE", false, DistortionModel::None},
    {2, "SIMPLE_RADIAL", true, DistortionModel::SimpleRadial},
    {3, "RADIAL", true, DistortionModel::Radial},
    {4, "OPENCV", false, DistortionModel::OpenCV},
    {6, "FULL_OPENCV", false, DistortionModel::FullOpenCV},
};

// The models above by name, comma-separated, for error messages.
std::string ColmapCameraModelList();

// Fills `c` (not its size) from MODEL's PARAMS[]. Returns the problem in plain words (an
// unsupported model, a wrong parameter count, a non-finite or non-positive value), or ""
// when the parameters describe a camera. Checks c.width and c.height too.
std::string SetColmapIntrinsics(const ColmapCameraModel* model, const std::string& model_name,
                                const std::vector<double>& params, ColmapIntrinsics& c);

// The number of PARAMS[] of the model with COLMAP id `id` (supported or not), or 0 for an
// id COLMAP does not define; and its name ("model id 42" for one COLMAP does not define).
size_t ColmapParameterCount(int id);
std::string ColmapModelName(int id);

// The image NAME of camera `c` at the pose (QW QX QY QZ, TX TY TZ): the quaternion rotates
// world into camera and is normalised here. Returns "zero quaternion" as `problem`.
ColmapImage MakeColmapImage(const std::string& name, const ColmapIntrinsics& c, const double q[4],
                            const double t[3], std::string* problem);

}  // namespace vkr::colmap_detail
