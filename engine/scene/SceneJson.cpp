#include "engine/scene/SceneJson.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>

#include "engine/common/InputError.h"
#include "engine/scene/Expression.h"

namespace vkr::scene_detail {
namespace {

std::string TypeName(const Json& j) {
  if (j.is_number()) return "a number";
  if (j.is_string()) return "a string " + j.dump();
  if (j.is_boolean()) return j.dump();
  if (j.is_null()) return "null";
  if (j.is_array()) return "a list";
  return "an object";
}

size_t EditDistance(const std::string& a, const std::string& b) {
  std::vector<size_t> row(b.size() + 1);
  for (size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (size_t i = 1; i <= a.size(); ++i) {
    size_t diagonal = row[0];
    row[0] = i;
    for (size_t j = 1; j <= b.size(); ++j) {
      const size_t up = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (a[i - 1] != b[j - 1])});
      diagonal = up;
    }
  }
  return row[b.size()];
}

// Tracks the JSON path during parsing to name a repeated key.
class DuplicateKeyCheck {
 public:
  DuplicateKeyCheck(std::string display) : display_(std::move(display)) {}

  bool operator()(int, Json::parse_event_t event, Json& parsed) {
    using E = Json::parse_event_t;
    switch (event) {
      case E::object_start:
      case E::array_start:
        frames_.push_back({event == E::object_start, ChildPath(), {}, {}, 0});
        break;
      case E::key: {
        Frame& f = frames_.back();
        f.key = parsed.get<std::string>();
        if (!f.keys.insert(f.key).second)
          throw InputError(display_, Join(f.path, f.key), "key appears twice in one object");
        break;
      }
      case E::object_end:
      case E::array_end:
        frames_.pop_back();
        ElementDone();
        break;
      case E::value:
        ElementDone();
        break;
    }
    return true;
  }

 private:
  struct Frame {
    bool object;
    std::string path;
    std::set<std::string> keys;
    std::string key;
    size_t index;
  };
  std::string ChildPath() const {
    if (frames_.empty()) return "";
    const Frame& f = frames_.back();
    return f.object ? Join(f.path, f.key) : Index(f.path, f.index);
  }
  void ElementDone() {
    if (!frames_.empty() && !frames_.back().object) ++frames_.back().index;
  }
  std::string display_;
  std::vector<Frame> frames_;
};

// Deeper than any scene, camera or value file needs (they nest four or five levels). The
// duplicate-key check keeps the JSON path of every open level, so a file nested n deep
// costs O(n²) time and memory: 100,000 '[' took minutes. Refused before parsing, so every
// file is read in time linear in its size.
constexpr int kMaxNesting = 64;

void CheckNesting(const std::string& text, const std::string& display) {
  int depth = 0;
  bool in_string = false;
  for (size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (in_string) {
      if (c == '\\') ++i;  // an escaped character, maybe a quote
      else if (c == '"') in_string = false;
    } else if (c == '"') {
      in_string = true;
    } else if (c == '[' || c == '{') {
      if (++depth > kMaxNesting)
        throw InputError(display, "", "malformed JSON: nesting deeper than " +
                                          std::to_string(kMaxNesting) + " levels at byte " +
                                          std::to_string(i + 1));
    } else if ((c == ']' || c == '}') && depth > 0) {
      --depth;  // unbalanced brackets are left to the parser, which names them better
    }
  }
}

}  // namespace

std::string Join(const std::string& path, const std::string& key) {
  return path.empty() ? key : path + "." + key;
}
std::string Index(const std::string& path, size_t i) {
  return path + "[" + std::to_string(i) + "]";
}

std::string Num(double v) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%g", v);
  return buffer;
}

Json ParseJsonFile(const std::filesystem::path& file, const std::string& display) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(file, ec))
    throw InputError(display, "", std::filesystem::exists(file, ec) ? "not a regular file"
                                                                       : "file not found");
  std::ifstream in(file, std::ios::binary);
  if (!in) throw InputError(display, "", "cannot open file");
  std::stringstream text;
  text << in.rdbuf();
  const std::string content = text.str();
  CheckNesting(content, display);
  try {
    return Json::parse(content, DuplicateKeyCheck(display));
  } catch (const Json::exception& e) {
    // what() is "[json.exception.parse_error.101] parse error at line L, column C: …", or
    // "[json.exception.out_of_range.406] number overflow parsing '1e999'".
    std::string message = e.what();
    if (const size_t p = message.find("] "); p != std::string::npos) message.erase(0, p + 2);
    if (e.id == 406) message += " (not a finite number)";
    throw InputError(display, "", "malformed JSON: " + message);
  }
}

void Reader::Fail(const std::string& field, const std::string& problem) const {
  throw InputError(file, field, problem);
}

void Reader::CheckObject(const Json& j, const std::string& path,
                         std::initializer_list<const char*> allowed) const {
  if (!j.is_object()) Fail(path, "expected an object, not " + TypeName(j));
  if (!strict) return;
  for (const auto& item : j.items()) {
    const std::string& key = item.key();  // not a structured binding: clang 14 cannot capture one
    if (std::any_of(allowed.begin(), allowed.end(), [&](const char* a) { return key == a; }))
      continue;
    std::string problem = "unknown key '" + key + "'";
    const char* best = nullptr;
    size_t best_distance = 3;  // suggest only near misses
    for (const char* a : allowed)
      if (const size_t d = EditDistance(key, a); d < best_distance) best = a, best_distance = d;
    if (best) problem += " (did you mean '" + std::string(best) + "'?)";
    if (overridden && overridden->count(Join(path, key))) problem += ", set by --set";
    Fail(Join(path, key), problem);
  }
}

const Json& Reader::Require(const Json& obj, const std::string& path, const char* key) const {
  const auto it = obj.find(key);
  if (it == obj.end()) Fail(Join(path, key), "missing (required)");
  return *it;
}

double Reader::Number(const Json& j, const std::string& path, const char* why) const {
  if (j.is_number()) {
    const double v = j.get<double>();
    if (!std::isfinite(v)) Fail(path, "number is not finite");
    return v;
  }
  if (j.is_string())
    return EvaluateConstantExpression(j.get<std::string>(), file, path,
                                      *why ? why : "settings are not parameters");
  Fail(path, std::string("expected a number, not ") + TypeName(j));
}

long long Reader::Integer(const Json& j, const std::string& path, long long lo,
                          long long hi) const {
  const std::string range = "an integer in [" + std::to_string(lo) + ", " + std::to_string(hi) + "]";
  if (j.is_number_unsigned()) {
    const auto v = j.get<unsigned long long>();
    if (v > static_cast<unsigned long long>(hi) || (lo > 0 && v < static_cast<unsigned long long>(lo)))
      Fail(path, "must be " + range + ", not " + j.dump());
    return static_cast<long long>(v);
  }
  double v = 0.0;
  if (j.is_number_integer()) v = double(j.get<long long>());
  else if (j.is_number_float()) v = j.get<double>();
  else Fail(path, "expected " + range + ", not " + TypeName(j));
  if (!std::isfinite(v) || v != std::floor(v) || v < double(lo) || v > double(hi))
    Fail(path, "must be " + range + ", not " + j.dump());
  return j.is_number_integer() ? j.get<long long>() : static_cast<long long>(v);
}

std::string Reader::String(const Json& j, const std::string& path) const {
  if (!j.is_string()) Fail(path, "expected a string, not " + TypeName(j));
  return j.get<std::string>();
}

Scalar Reader::ParseScalar(const Json& j, const std::string& path) const {
  Scalar s;
  if (j.is_number()) {
    s.constant = Number(j, path);
    return s;
  }
  if (!j.is_string())
    Fail(path, "expected a number or an expression string, not " + TypeName(j));
  const std::string text = j.get<std::string>();
  const int id = table->Compile(text, file, path);
  if (!table->UsedParameters(id).empty()) {
    s.expression = id;
    return s;
  }
  // A parameter-free expression ("0.5*sqrt(2)") is a constant: fold it now, so no
  // hypothesis ever pays for it.
  const std::vector<double> unused(table->parameter_names().size(), 0.0);
  s.constant = table->Evaluate(id, unused);
  if (!std::isfinite(s.constant))
    Fail(path, "expression \"" + text + "\" is not finite (" + std::to_string(s.constant) + ")");
  return s;
}

void Reader::ParseTriple(const Json& j, const std::string& path, Scalar out[3]) const {
  if (!j.is_array() || j.size() != 3) Fail(path, "expected a list of 3 values");
  for (size_t i = 0; i < 3; ++i) out[i] = ParseScalar(j[i], Index(path, i));
}

std::vector<Transform> Reader::Transforms(const Json& j, const std::string& path,
                                          bool allow_scale) const {
  if (!j.is_array()) Fail(path, "expected a list of transforms, not " + TypeName(j));
  std::vector<Transform> chain;
  for (size_t i = 0; i < j.size(); ++i) {
    const std::string at = Index(path, i);
    const Json& t = j[i];
    if (!t.is_object() || t.size() != 1)
      Fail(at, "expected one of {\"translate\": [x,y,z]}, {\"rotate\": [rx,ry,rz]}, "
               "{\"scale\": [sx,sy,sz]}");
    const std::string key = t.begin().key();
    Transform tr;
    if (key == "translate") tr.kind = Transform::Kind::Translate;
    else if (key == "rotate") tr.kind = Transform::Kind::Rotate;
    else if (key == "scale" && allow_scale) tr.kind = Transform::Kind::Scale;
    else if (key == "scale")
      Fail(Join(at, key), "a camera pose may only translate and rotate (a scaled camera "
                          "would no longer be a rigid motion)");
    else Fail(Join(at, key), "unknown transform '" + key + "' (translate, rotate, scale)");
    ParseTriple(t.begin().value(), Join(at, key), tr.value);
    chain.push_back(tr);
  }
  return chain;
}

std::filesystem::path Reader::ExistingFile(const Json& j, const std::string& path,
                                           const char* what) const {
  const std::string value = String(j, path);
  if (value.empty()) Fail(path, std::string("empty ") + what + " name");
  const std::filesystem::path p = (dir / value).lexically_normal();
  std::error_code ec;
  if (!std::filesystem::is_regular_file(p, ec))
    Fail(path, std::string(what) + " " + Display(p) + " not found");
  return p;
}

std::string Reader::Display(const std::filesystem::path& p) const {
  const std::filesystem::path rel = p.lexically_relative(dir);
  if (rel.empty() || *rel.begin() == "..") return p.string();
  return rel.string();
}

}  // namespace vkr::scene_detail
