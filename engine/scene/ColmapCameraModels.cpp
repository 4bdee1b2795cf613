#include "engine/scene/ColmapCameraModels.h"

#include <Eigen/Geometry>
#include <cmath>

namespace vkr::colmap_detail {

std::string ColmapCameraModelList() {
  std::string list;
  for (const ColmapCameraModel& m : kColmapCameraModels)
    list += (list.empty() ? "" : ", ") + std::string(m.name);
  return list;
}

std::string SetColmapIntrinsics(const ColmapCameraModel* model, const std::string& model_name,
                                const std::vector<double>& params, ColmapIntrinsics& c) {
  if (!model)
    return "camera model " + model_name + " is not supported (supported: " + ColmapCameraModelList() + ")";
  const size_t focals = model->single_focal ? 1 : 2;
  const size_t expected = focals + 2 + CoefficientNames(model->distortion).size();
  if (params.size() != expected)
    return model_name + " needs " + std::to_string(expected) + " parameters, not " + std::to_string(params.size());
  for (double v : params)
    if (!std::isfinite(v)) return "camera parameters must be finite";
  c.fx = params[0];
  c.fy = params[focals - 1];
  c.cx = params[focals];
  c.cy = params[focals + 1];
  c.distortion = LensDistortion{};
  c.distortion.model = model->distortion;
  for (size_t k = focals + 2; k < params.size(); ++k) c.distortion.coefficients[k - focals - 2] = params[k];
  if (c.width <= 0 || c.height <= 0 || !(c.fx > 0) || !(c.fy > 0))
    return "camera size and focal length must be positive";
  return "";
}

namespace {
// Every model COLMAP defines (src/colmap/sensor/models.h), by id: name and PARAMS[] count.
struct AnyColmapModel {
  const char* name;
  size_t params;
};
constexpr AnyColmapModel kAnyColmapModel[] = {
    {"SIMPLE_PINHOLE", 3}, {"PINHOLE", 4},        {"SIMPLE_RADIAL", 4},
    {"RADIAL", 5},         {"OPENCV", 8},         {"OPENCV_FISHEYE", 8},
    {"FULL_OPENCV", 12},   {"FOV", 5},            {"SIMPLE_RADIAL_FISHEYE", 4},
    {"RADIAL_FISHEYE", 5}, {"THIN_PRISM_FISHEYE", 12}, {"RAD_TAN_THIN_PRISM_FISHEYE", 16},
};
}  // namespace

size_t ColmapParameterCount(int id) {
  return id >= 0 && id < int(std::size(kAnyColmapModel)) ? kAnyColmapModel[id].params : 0;
}

std::string ColmapModelName(int id) {
  return ColmapParameterCount(id) ? kAnyColmapModel[id].name : "model id " + std::to_string(id);
}

ColmapImage MakeColmapImage(const std::string& name, const ColmapIntrinsics& c, const double q[4],
                            const double t[3], std::string* problem) {
  ColmapImage im;
  const Eigen::Quaterniond quat(q[0], q[1], q[2], q[3]);
  if (!(quat.norm() > 1e-12)) {
    *problem = "zero quaternion";
    return im;
  }
  im.name = std::filesystem::path(name).stem().string();
  im.image = name;
  im.width = c.width, im.height = c.height;
  im.fx = c.fx, im.fy = c.fy, im.cx = c.cx, im.cy = c.cy;
  im.distortion = c.distortion;
  im.R = quat.normalized().toRotationMatrix();
  im.t = Eigen::Vector3d(t[0], t[1], t[2]);
  return im;
}

}  // namespace vkr::colmap_detail
