#pragma once
// The scene model: what a scene file describes, independent of Vulkan
// (docs/guide/SCENE_FORMAT.md): parameters, nodes and cameras. A Scene is immutable after
// loading; a hypothesis Ψ is a vector of parameter values in the order of Scene::parameters,
// and the scene turns it into node matrices and cameras.

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstdint>
#include <filesystem>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "engine/scene/LensDistortion.h"

namespace vkr {

class ExpressionTable;
namespace scene_detail {
struct SceneAccess;  // lets the loader install the expression table
}

// A number in a scene file: a constant, or an expression over parameter names
// compiled once into the scene's ExpressionTable.
struct Scalar {
  double constant = 0.0;
  int expression = -1;  // index into ExpressionTable; -1 means `constant`
  bool IsConstant() const { return expression < 0; }
};

// A parameter's prior. Uniform: a = lo, b = hi. Normal: a = mean, b = sd.
struct Prior {
  enum class Kind { Uniform, Normal };
  Kind kind = Kind::Uniform;
  double a = 0.0, b = 1.0;

  // Log density up to a constant; -infinity outside a uniform's support.
  double LogDensity(double x) const;
  // Scale of the prior: hi - lo, or 4 sd. Proposal widths and errors are relative to it.
  double Width() const;
  // Mean of the prior (the starting point when a parameter has no `init`).
  double Centre() const;
};

struct Parameter {
  std::string name;
  Prior prior;
  // Hard limits; a normal prior without bounds is unbounded.
  std::optional<std::pair<double, double>> bounds;
  std::optional<double> init;
  // `init`, else the prior's centre clamped into the bounds.
  double Initial() const;
  // Whether x lies inside the prior's support and the bounds.
  bool Admissible(double x) const;
};

enum class PrimitiveKind { None, Plane, Box, Prism, Cylinder, Mesh };
const char* ToString(PrimitiveKind kind);

// One component of a node's or camera's transform chain.
struct Transform {
  enum class Kind { Translate, Rotate, Scale };
  Kind kind = Kind::Translate;
  Scalar value[3];  // metres, degrees (rotations applied z·y·x), or factors
};

struct Node {
  std::string name;
  int parent = -1;  // index into Scene::nodes; parents always precede children
  PrimitiveKind primitive = PrimitiveKind::None;
  std::filesystem::path mesh;    // absolute path, for PrimitiveKind::Mesh
  std::filesystem::path albedo;  // absolute path, or empty
  std::vector<Transform> transforms;  // first outermost: world = parent · T1 · T2 · …
};

// A camera as written in the scene (entries may be expressions).
struct CameraModel {
  std::string name;
  std::filesystem::path image;  // absolute path
  int width = 0, height = 0;
  Scalar K[9];  // row-major, upper triangular
  Eigen::Matrix3d R = Eigen::Matrix3d::Identity();
  Eigen::Vector3d t = Eigen::Vector3d::Zero();
  // Optional transforms that move the camera in the world:
  // world_from_cam' = pose · world_from_cam.
  std::vector<Transform> pose;
  // The lens (None: a pinhole). A camera with distortion has a constant K: its photograph
  // is undistorted once, with that K, when it is loaded (pipelines/rendering/LensWarp.h).
  LensDistortion distortion;
  // The validity mask (absolute path, 0 = ignore that pixel), or empty: every pixel counts.
  // Found by the masks folder rule of docs/guide/SCENE_FORMAT.md, "Masks".
  std::filesystem::path mask;
  // The scene's `max_side` shrinks the photograph by this integer factor (Photographs.h):
  // width and height are then the shrunk size, and K is divided by it in Scene::Cameras.
  int shrink = 1;
};

// A camera evaluated at one hypothesis. OpenCV convention: x_cam = R·X + t, the camera
// looks down +z, image y points down, the image spans [0,W]×[0,H] and pixel (i, j) has its
// centre at (i+0.5, j+0.5).
struct Camera {
  std::string name;
  std::filesystem::path image;
  int width = 0, height = 0;
  Eigen::Matrix3d K = Eigen::Matrix3d::Identity();
  Eigen::Matrix4d cam_from_world = Eigen::Matrix4d::Identity();
  // Applied to normalised coordinates between cam_from_world and K (LensDistortion.h).
  LensDistortion distortion;
  int shrink = 1;  // load `image` with LoadPhotograph(image, shrink) (Photographs.h)

  Eigen::Matrix3d R() const { return cam_from_world.topLeftCorner<3, 3>(); }
  Eigen::Vector3d t() const { return cam_from_world.topRightCorner<3, 1>(); }
  Eigen::Vector3d Centre() const { return -R().transpose() * t(); }
  // Pixel coordinates of a world point through the pinhole K, without the lens's
  // distortion (no check that it is in front).
  Eigen::Vector2d Project(const Eigen::Vector3d& world) const;
};

// cam_from_world of a camera at `eye` looking at `target` with world z up (image y down);
// straight up or down, image x is world x.
Eigen::Matrix4d CamFromWorldLookingAt(const Eigen::Vector3d& eye, const Eigen::Vector3d& target);

// `--set PATH=VALUE` overrides, applied to the JSON before it is interpreted.
struct SceneOverride {
  std::string path;   // dotted path, e.g. "likelihood.sigma" or "sampler.seed"
  std::string value;  // parsed as JSON if it parses, else taken as a string
};

class Scene {
 public:
  Scene();  // empty: no parameters, nodes or cameras; LoadScene fills one in
  ~Scene();
  Scene(Scene&&) noexcept;
  Scene& operator=(Scene&&) noexcept;

  std::filesystem::path file;        // the scene file (absolute)
  std::filesystem::path images_dir;  // where camera images resolve (absolute)
  // The longest side a photograph is used at (0: as it is); larger ones are shrunk by an
  // integer factor on load (Photographs.h).
  int max_side = 0;
  // The overrides it was loaded with: with `file`, how to load it again (a run records both,
  // and loads it again at another atlas side).
  std::vector<SceneOverride> overrides;
  std::vector<Parameter> parameters;
  std::vector<Node> nodes;
  std::vector<CameraModel> cameras;
  // The settings blocks ("likelihood", "sampler", "synth") as JSON text, as the file and its
  // overrides wrote them; absent where the file has none. Each belongs to the layer that uses
  // it, which reads it with a SettingsReader (SettingsReader.h says which type is whose).
  std::map<std::string, std::string> settings;

  int ParameterIndex(const std::string& name) const;  // -1 if absent
  std::vector<double> InitialValues() const;

  // Reads an `--at` file ({"name": value, …}). Every parameter must be given, and no
  // unknown name; otherwise InputError naming the file and the key.
  std::vector<double> ValuesFromFile(const std::filesystem::path& at_file) const;
  // Writes values in the same format.
  void WriteValues(const std::filesystem::path& file, const std::vector<double>& psi) const;

  double Evaluate(const Scalar& s, const std::vector<double>& psi) const;
  // world_from_node for every node, in the order of `nodes`.
  std::vector<Eigen::Matrix4d> WorldFromNode(const std::vector<double>& psi) const;
  std::vector<Camera> Cameras(const std::vector<double>& psi) const;

  ExpressionTable& expressions() { return *expressions_; }
  const ExpressionTable& expressions() const { return *expressions_; }

 private:
  friend struct scene_detail::SceneAccess;
  std::unique_ptr<ExpressionTable> expressions_;
};

// Splits command-line `--set PATH=VALUE` strings. Path fields (images, cameras, masks,
// …albedo, …mesh) typed relative are made absolute: on the command line they are relative to
// where the user is, not to the scene file. Throws InputError("", "--set", …) without '='.
std::vector<SceneOverride> ParseOverrides(const std::vector<std::string>& sets);

// What LoadScene checks beyond the scene file itself.
struct LoadOptions {
  // Whether every camera's image must exist and match the camera's size. `vkrecon synth`
  // turns this off: it is about to create the images.
  bool require_images = true;
};

// Loads and validates a scene file. Throws InputError (file, JSON path, problem) for every
// bad input listed in docs/guide/SCENE_FORMAT.md, "Errors". Nodes must be listed parents first (a
// child before its parent is an error), so node indices are the file's order.
Scene LoadScene(const std::filesystem::path& file,
                const std::vector<SceneOverride>& overrides = {},
                const LoadOptions& options = {});

// The 4×4 matrix of a transform chain at Ψ: T1 · T2 · …
Eigen::Matrix4d ComposeTransforms(const Scene& scene, const std::vector<Transform>& chain,
                                  const std::vector<double>& psi);

}  // namespace vkr
