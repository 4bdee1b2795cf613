#include "engine/scene/LensDistortion.h"

#include <Eigen/LU>
#include <cmath>
#include <locale>
#include <set>
#include <sstream>
#include <stdexcept>

#include "engine/common/InputError.h"

namespace vkr {
namespace {

constexpr DistortionModel kModels[] = {DistortionModel::SimpleRadial, DistortionModel::Radial,
                                       DistortionModel::OpenCV, DistortionModel::FullOpenCV};

// The eight FULL_OPENCV coefficients k1 k2 p1 p2 k3 k4 k5 k6 of any model: the one formula
// below serves all of them (a model's missing coefficients are zero).
std::array<double, 8> FullCoefficients(const LensDistortion& d) {
  std::array<double, 8> full{};
  const std::vector<std::string>& names = CoefficientNames(DistortionModel::FullOpenCV);
  const std::vector<std::string>& mine = CoefficientNames(d.model);
  for (size_t i = 0; i < mine.size(); ++i) {
    // SIMPLE_RADIAL's k is k1.
    const std::string name = mine[i] == "k" ? "k1" : mine[i];
    for (size_t j = 0; j < names.size(); ++j)
      if (names[j] == name) full[j] = d.coefficients[i];
  }
  return full;
}

}  // namespace

const char* ToString(DistortionModel model) {
  switch (model) {
    case DistortionModel::None: return "NONE";
    case DistortionModel::SimpleRadial: return "SIMPLE_RADIAL";
    case DistortionModel::Radial: return "RADIAL";
    case DistortionModel::OpenCV: return "OPENCV";
    case DistortionModel::FullOpenCV: return "FULL_OPENCV";
  }
  return "?";
}

bool FromString(const std::string& name, DistortionModel* model) {
  for (DistortionModel m : kModels)
    if (name == ToString(m)) {
      *model = m;
      return true;
    }
  return false;
}

const std::vector<std::string>& CoefficientNames(DistortionModel model) {
  static const std::vector<std::string> none, simple{"k"}, radial{"k1", "k2"},
      opencv{"k1", "k2", "p1", "p2"}, full{"k1", "k2", "p1", "p2", "k3", "k4", "k5", "k6"};
  switch (model) {
    case DistortionModel::None: return none;
    case DistortionModel::SimpleRadial: return simple;
    case DistortionModel::Radial: return radial;
    case DistortionModel::OpenCV: return opencv;
    case DistortionModel::FullOpenCV: return full;
  }
  return none;
}

std::string DistortionModelList() {
  std::string list;
  for (DistortionModel m : kModels) list += (list.empty() ? "" : ", ") + std::string(ToString(m));
  return list;
}

double LensDistortion::Coefficient(const std::string& name) const {
  const std::vector<std::string>& names = CoefficientNames(model);
  for (size_t i = 0; i < names.size(); ++i)
    if (names[i] == name) return coefficients[i];
  throw std::invalid_argument(std::string("LensDistortion: ") + ToString(model) + " has no coefficient " + name);
}

Eigen::Vector2d LensDistortion::Distort(const Eigen::Vector2d& p, Eigen::Matrix2d* jacobian) const {
  if (IsNone()) {
    if (jacobian) jacobian->setIdentity();
    return p;
  }
  const auto [k1, k2, p1, p2, k3, k4, k5, k6] = FullCoefficients(*this);
  const double x = p.x(), y = p.y();
  const double r2 = x * x + y * y;
  const double num = 1.0 + r2 * (k1 + r2 * (k2 + r2 * k3));
  const double den = 1.0 + r2 * (k4 + r2 * (k5 + r2 * k6));
  const double radial = num / den;
  const Eigen::Vector2d out(x * radial + 2.0 * p1 * x * y + p2 * (r2 + 2.0 * x * x),
                            y * radial + p1 * (r2 + 2.0 * y * y) + 2.0 * p2 * x * y);
  if (jacobian) {
    // d radial / d r², then the chain rule through r² = x² + y².
    const double dnum = k1 + r2 * (2.0 * k2 + 3.0 * r2 * k3);
    const double dden = k4 + r2 * (2.0 * k5 + 3.0 * r2 * k6);
    const double dradial = (dnum * den - num * dden) / (den * den);
    const double cross = 2.0 * x * y * dradial + 2.0 * p1 * x + 2.0 * p2 * y;
    (*jacobian) << radial + 2.0 * x * x * dradial + 2.0 * p1 * y + 6.0 * p2 * x, cross,
        cross, radial + 2.0 * y * y * dradial + 6.0 * p1 * y + 2.0 * p2 * x;
  }
  return out;
}

std::array<double, 8> LensDistortion::FullOpenCV() const { return FullCoefficients(*this); }

bool LensDistortion::Undistort(const Eigen::Vector2d& distorted, Eigen::Vector2d* undistorted) const {
  if (IsNone()) {
    *undistorted = distorted;
    return true;
  }
  // Newton on D(x) − x_d = 0 from x = x_d: for real lenses D is close to the identity
  // near the image, so this converges in a handful of steps (quadratically). Fixed-point
  // iteration (OpenCV's) converges only linearly and stalls where |D − I| is large.
  Eigen::Vector2d x = distorted;
  for (int step = 0; step < 50; ++step) {
    Eigen::Matrix2d J;
    const Eigen::Vector2d residual = Distort(x, &J) - distorted;
    if (!residual.allFinite()) return false;
    if (residual.norm() < 1e-12) {
      *undistorted = x;
      return true;
    }
    const double det = J.determinant();
    if (!(std::abs(det) > 1e-12)) return false;  // a fold of the lens map: no unique ray
    x -= J.inverse() * residual;
  }
  return false;
}

LensDistortion ParseDistortionSpec(const std::string& spec, const std::string& option) {
  auto fail = [&](const std::string& problem) -> LensDistortion { throw InputError("", option, problem); };
  LensDistortion d;
  const size_t colon = spec.find(':');
  const std::string name = spec.substr(0, colon);
  if (!FromString(name, &d.model))
    return fail("unknown distortion model '" + name + "' (" + DistortionModelList() + ")");
  if (colon == std::string::npos) return d;
  const std::vector<std::string>& names = CoefficientNames(d.model);
  std::set<std::string> seen;
  std::istringstream list(spec.substr(colon + 1));
  for (std::string item; std::getline(list, item, ',');) {
    const size_t eq = item.find('=');
    const std::string key = item.substr(0, eq);
    size_t index = 0;
    while (index < names.size() && names[index] != key) ++index;
    if (eq == std::string::npos || index == names.size()) {
      std::string known;
      for (const std::string& n : names) known += (known.empty() ? "" : ", ") + n;
      return fail("'" + item + "': " + name + " takes NAME=VALUE with NAME one of " + known);
    }
    if (!seen.insert(key).second) return fail(key + " is given twice");
    std::istringstream number(item.substr(eq + 1));
    number.imbue(std::locale::classic());
    double value = 0.0;
    if (!(number >> value) || !(number >> std::ws).eof() || !std::isfinite(value))
      return fail(key + ": '" + item.substr(eq + 1) + "' is not a finite number");
    d.coefficients[index] = value;
  }
  return d;
}

}  // namespace vkr
