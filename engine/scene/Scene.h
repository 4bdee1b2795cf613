#pragma once
// The scene model: what a scene file describes, independent of Vulkan
// (docs/guide/SCENE_FORMAT.md). A Scene is immutable after loading; a hypothesis Ψ is a vector of
// parameter values in the order of Scene::parameters, and the scene turns it into node
// matrices and cameras.

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

struct LikelihoodSettings {
  std::string kind = "surface";  // "surface" | "image"
  double sigma = 8.0;            // noise sd on the 0–255 scale
  // `"sigma": "auto"` (the default): the run estimates σ from the data. `sigma` then keeps
  // its default, which a consumer that cannot estimate σ may use.
  bool sigma_auto = true;
  std::string weights = "angle"; // "uniform" | "angle"
  // Atlas side in texels and pyramid levels; 0 = "auto" (the default), sized from the
  // cameras' footprint of the surface by ResolveAutoLikelihood (engine/geometry/
  // AtlasFootprint.h), which every command that builds a likelihood calls after loading.
  int atlas = 0;
  int levels = 0;
  // How the atlas shares its texels among the faces (engine/geometry/Atlas.h): "area" (the
  // default), the same texels per metre everywhere; "pixels", in proportion to the pixels
  // each face covers in the camera that sees it largest at the initial values, so surface
  // the photographs show in detail is not starved by a wide ground they see obliquely.
  std::string charts = "area";
  // Per-camera colour correction of the surface likelihood: "none", "gain" or "affine"
  // (pipelines/model/Photometric.h).
  std::string photometric = "affine";
  // Whether each hypothesis of a batch gets its own GPU images: "auto" | "shared" | "per_slot"
  // (pipelines/likelihood/SurfaceLikelihood.h, SlotImages).
  std::string slot_images = "auto";
  // Mask what the photographs show that the scene leaves out, found at the mode a run
  // settles on (pipelines/likelihood/ClutterMasks.h).
  bool clutter = true;
  // The edge term of the surface likelihood (pipelines/model/EdgeEvidence.h): the model's
  // contours and creases should lie on the photographs' edges.
  bool edges = false;
  // Texels per side of the blocks behind κ, the sandwich factor (pipelines/likelihood/
  // NoiseCalibration.h): 8, 16, 32 or 64; 0 ("auto", the default) takes the largest κ over
  // those sizes.
  int sandwich_blocks = 0;
  // How the sandwich adjusts the log-likelihood (NoiseCalibration.h): "magnitude" divides it
  // by κ, the mean of H⁻¹J's eigenvalues, in every direction alike; "curvature" gives each
  // direction its own factor, so the posterior's covariance is the sandwich H⁻¹JH⁻¹.
  std::string sandwich_adjustment = "magnitude";
  // κ, the factor the log-likelihood is divided by. A number fixes it, so that runs of several
  // scenes score one likelihood (`vkrecon compare`, docs/guide/WHICH_SCENE.md); 0 estimates it
  // at the mode as `kappa_estimate` says: "sandwich" by the block sandwich (NoiseCalibration.h),
  // "noise" from the residuals' own correlation (NoiseCorrelation.h), "auto" (the default)
  // samples with the sandwich's and states the intervals at the noise's where the diagnosis
  // finds no model error (recon/NoiseIntervals.h).
  double kappa = 0.0;
  std::string kappa_estimate = "auto";
  // δ in pixels, the noise's texture term (σ² + δ²|∇I|²): used as given with a fixed `sigma`,
  // estimated with it under "auto".
  double position_sd = 0.5;
  // The image-space likelihood only (docs/internals/IMAGE_SPACE.md): 0 compares every ordered
  // camera pair; k > 0 each target camera with its k best sources, ranked by `partner_ranking`
  // ("distance": nearest centres, "direction": most similar optical axes).
  int partners = 0;
  std::string partner_ranking = "distance";
};

// sampler.time_limit's default: a run a user starts at a desk ends within minutes on a CPU
// device (lavapipe), converged or not; the report and the diagnosis say which.
constexpr double kDefaultTimeLimit = 240.0;

// The most hypotheses one submission may take (sampler.batch; SceneLoader.cpp says why).
constexpr int kMaxSamplerBatch = 4096;

struct SamplerSettings {
  // `"iterations": "auto"` (the default): sample until the chains converge (R̂ ≤ 1.01,
  // bulk-ESS ≥ 400) or time_limit; `iterations` then lays out the exploration and burn-in
  // only (SamplerOptions::until_converged). A number: exactly that many.
  bool iterations_auto = true;
  int iterations = 600;
  // Seconds the sampling may take before it ends where it is (0 = none; below 0, the
  // default: kDefaultTimeLimit with "auto" iterations, none with a fixed count). The
  // refinement and the outputs come after it.
  double time_limit = -1.0;
  double TimeLimit() const { return time_limit >= 0.0 ? time_limit : iterations_auto ? kDefaultTimeLimit : 0.0; }
  int chains = 4;
  int batch = 16;
  std::uint64_t seed = 1;
  // Any further fields of the scene's "sampler" object as JSON text ("{}" when none):
  // SamplerOptions by name, validated by `vkrecon run` (docs/guide/SCENE_FORMAT.md).
  std::string options_json = "{}";
};

// How `vkrecon synth` renders the scene unless its command line says otherwise: reference
// images that look like photographs (a sun with cast shadows, exposure that differs between
// cameras, anti-aliasing). The defaults draw the albedo as it is, as earlier versions did.
struct SynthSettings {
  bool sun = false;              // light the scene with a sun and ambient sky light
  double sun_azimuth = 135.0;    // degrees, from +x towards +y
  double sun_elevation = 50.0;   // degrees above the horizon
  double ambient = 0.3;          // share of the light that comes from the sky, on every face
  double exposure = 0.0;         // spread of each camera's exposure (gain ±spread, see Exposure.h)
  int supersample = 1;           // samples per pixel along each axis (anti-aliasing)
};

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
  LikelihoodSettings likelihood;
  SamplerSettings sampler;
  SynthSettings synth;

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
