#pragma once
// Internal to engine/scene: reading typed values out of a scene or camera file with the
// JSON path of every value at hand, so each error names file, path and problem in one line
// (docs/guide/SCENE_FORMAT.md, "Errors").
// Objects keep the file's key order (ordered_json): the order of `parameters` is the
// order of Ψ.

#include <filesystem>
#include <initializer_list>
#include <nlohmann/json.hpp>
#include <set>
#include <string>
#include <vector>

#include "engine/scene/Scene.h"

namespace vkr::scene_detail {

using Json = nlohmann::ordered_json;

// "a.b" / "a[3]" path building; an empty parent gives just the key.
std::string Join(const std::string& path, const std::string& key);
std::string Index(const std::string& path, size_t i);
// A number for a message ("%g").
std::string Num(double v);

// Installs what only the loader may set in a Scene.
struct SceneAccess {
  static void SetExpressions(Scene& scene, std::unique_ptr<ExpressionTable> table);
};

// Reads and parses a JSON file. Malformed JSON → InputError(display, "", "… at line L,
// column C: …"); a key repeated inside one object → InputError naming its path (JSON
// parsers silently keep the last one, which would be a silent default).
Json ParseJsonFile(const std::filesystem::path& file, const std::string& display);

// Applies `--set PATH=VALUE` overrides in order (docs/guide/SCENE_FORMAT.md, "Overrides"), creating
// missing object keys. Returns the paths set, so a later "unknown key" can say it came
// from the command line.
std::set<std::string> ApplyOverrides(Json& root, const std::vector<SceneOverride>& overrides,
                                     const std::string& display);

// Reading context for one file.
struct Reader {
  std::string file;                     // shown in errors (as the user would recognise it)
  std::filesystem::path dir;            // absolute folder that relative paths resolve against
  ExpressionTable* table = nullptr;     // where expressions compile; null: numbers only
  bool strict = true;                   // unknown keys are errors (scene file) or ignored
  const std::set<std::string>* overridden = nullptr;

  [[noreturn]] void Fail(const std::string& field, const std::string& problem) const;

  // Unknown keys are errors in the scene file (usually typos), ignored in camera files
  // written by other tools. Also fails if `j` is not an object.
  void CheckObject(const Json& j, const std::string& path,
                   std::initializer_list<const char*> allowed) const;
  const Json& Require(const Json& obj, const std::string& path, const char* key) const;

  // A finite number, or a parameter-free expression string (`why` says why it must be
  // constant).
  double Number(const Json& j, const std::string& path, const char* why = "") const;
  long long Integer(const Json& j, const std::string& path, long long lo, long long hi) const;
  std::string String(const Json& j, const std::string& path) const;
  // A number or an expression over parameters. Parameter-free expressions fold into
  // constants; others compile into `table`.
  Scalar ParseScalar(const Json& j, const std::string& path) const;
  // [a, b, c] of ParseScalar.
  void ParseTriple(const Json& j, const std::string& path, Scalar out[3]) const;
  // A transform chain: [{"translate": [..]}, {"rotate": [..]}, {"scale": [..]}].
  std::vector<Transform> Transforms(const Json& j, const std::string& path,
                                    bool allow_scale) const;
  // `dir / value`, which must name an existing regular file; `what` is e.g. "mesh file".
  std::filesystem::path ExistingFile(const Json& j, const std::string& path,
                                     const char* what) const;
  // `p` relative to `dir` where it lies inside, for messages.
  std::string Display(const std::filesystem::path& p) const;
};

// Reads the `cameras` value of the scene file (file name, inline list, or COLMAP model;
// docs/guide/SCENE_FORMAT.md, "cameras") into scene.cameras. Camera images resolve against
// scene.images_dir.
void ReadCameras(const Json& value, const Reader& scene_reader, bool require_images,
                 Scene& scene);

// Finds each camera's mask (MaskLoader.cpp: the scene's `masks` folder, `value`, or
// without one `masks/` beside the images folder) and, with `require_images`, checks that it
// is readable and of its camera's size.
void ResolveMasks(const Json* value, const Reader& scene_reader, bool require_images, Scene& scene);

}  // namespace vkr::scene_detail
