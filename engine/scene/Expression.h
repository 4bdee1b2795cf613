#pragma once
// Expressions over parameter names (docs/guide/SCENE_FORMAT.md, "Numbers and expressions":
// a number may be an expression such as "2*rise" or "rh/h"). Each expression is compiled once, at
// load time, by muParser into byte code bound to one internal value array; evaluating it at a
// hypothesis Ψ copies Ψ into that array and runs the byte code. No parsing happens per hypothesis.

#include <memory>
#include <mutex>
#include <string>
#include <vector>

namespace vkr {

class ExpressionTable {
 public:
  // `parameter_names` in the order of Scene::parameters (= the order of Ψ). Throws
  // InputError naming `file` and `parameters.NAME` if a name cannot be a muParser variable
  // (not an identifier, or the name of a built-in function or constant such as `sin`, `_pi`).
  ExpressionTable(std::vector<std::string> parameter_names, const std::string& file);
  ~ExpressionTable();
  ExpressionTable(const ExpressionTable&) = delete;
  ExpressionTable& operator=(const ExpressionTable&) = delete;

  // Compiles `text`, found at JSON path `field` of `file`, and returns its id. Throws
  // InputError(file, field, …) for a syntax error (with muParser's message), a name that is
  // not a declared parameter, an assignment, or a list of several expressions.
  int Compile(const std::string& text, const std::string& file, const std::string& field);

  // Value of expression `id` at Ψ (psi.size() must equal the number of parameters).
  // Thread-safe: a mutex guards the shared value array, which costs far less than the
  // evaluation itself.
  double Evaluate(int id, const std::vector<double>& psi) const;

  int size() const { return int(entries_.size()); }
  const std::string& Text(int id) const;
  // Where the expression was written, for error messages after loading.
  const std::string& File(int id) const;
  const std::string& Field(int id) const;
  // Indices (into Ψ) of the parameters the expression reads, ascending.
  const std::vector<int>& UsedParameters(int id) const;
  // Whether any compiled expression reads parameter `index`.
  bool IsUsed(int index) const { return used_[size_t(index)]; }
  const std::vector<std::string>& parameter_names() const { return names_; }

 private:
  struct Entry;
  std::vector<std::string> names_;
  std::vector<bool> used_;
  // Stable storage for the muParser variables: allocated once, never resized, because
  // every compiled parser holds pointers into it.
  std::unique_ptr<double[]> values_;
  // mu::Parser must not be copied or moved once variables are defined: one heap entry each.
  std::vector<std::unique_ptr<Entry>> entries_;
  mutable std::mutex mutex_;
};

// Evaluates an expression that must not read any parameter (e.g. "0.5*sqrt(2)" inside a
// camera's R). Throws InputError(file, field, …) on a syntax error, on any name (parameters
// are not allowed here: `why_constant` says why, e.g. "R is fixed; use \"pose\" to move a
// camera"), or on a non-finite result.
double EvaluateConstantExpression(const std::string& text, const std::string& file,
                                  const std::string& field, const std::string& why_constant);

}  // namespace vkr
