#include "engine/scene/Expression.h"

#include <muParser.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <stdexcept>

#include "engine/common/InputError.h"

namespace vkr {

struct ExpressionTable::Entry {
  mu::Parser parser;
  std::string text, file, field;
  std::vector<int> used;
};

namespace {

// muParser treats `x = 1` (and `+=`, `-=`, …) as an assignment to a variable. A scene value
// must not change a parameter, so any '=' that is not part of ==, <=, >=, != is refused.
bool HasAssignment(const std::string& text) {
  for (size_t i = 0; i < text.size(); ++i) {
    if (text[i] != '=') continue;
    if (i + 1 < text.size() && text[i + 1] == '=') {
      ++i;
      continue;
    }
    if (i > 0 && (text[i - 1] == '<' || text[i - 1] == '>' || text[i - 1] == '!')) continue;
    return true;
  }
  return false;
}

std::string Quoted(const std::string& text) { return "\"" + text + "\""; }

// muParser reads a number it cannot represent ("1e999") as a name; say what it really is.
std::string NameProblem(const std::string& name, const std::string& text) {
  if (!name.empty() && std::isdigit(static_cast<unsigned char>(name[0])))
    return "number '" + name + "' in expression " + Quoted(text) + " is not finite";
  return "";
}

void CheckForm(const std::string& text, const std::string& file, const std::string& field) {
  if (text.find_first_not_of(" \t") == std::string::npos)
    throw InputError(file, field, "empty expression");
  if (HasAssignment(text))
    throw InputError(file, field,
                     "expression " + Quoted(text) + " assigns a value; only formulas are allowed");
}

}  // namespace

ExpressionTable::ExpressionTable(std::vector<std::string> parameter_names,
                                 const std::string& file)
    : names_(std::move(parameter_names)),
      used_(names_.size(), false),
      values_(new double[std::max<size_t>(names_.size(), 1)]()) {
  // Validate every name once against a scratch parser, so Compile cannot fail on a name.
  mu::Parser probe;
  for (size_t i = 0; i < names_.size(); ++i) {
    const std::string& name = names_[i];
    const std::string field = "parameters." + name;
    if (probe.GetFunDef().count(name))
      throw InputError(file, field, "'" + name + "' is the name of a built-in function");
    try {
      probe.DefineVar(name, &values_[i]);
    } catch (const mu::Parser::exception_type& e) {
      throw InputError(file, field,
                       "'" + name + "' cannot be a parameter name (" + e.GetMsg() +
                           "); use letters, digits and '_', not starting with a digit");
    }
  }
}

ExpressionTable::~ExpressionTable() = default;

int ExpressionTable::Compile(const std::string& text, const std::string& file,
                             const std::string& field) {
  CheckForm(text, file, field);
  auto entry = std::make_unique<Entry>();
  entry->text = text;
  entry->file = file;
  entry->field = field;
  try {
    for (size_t i = 0; i < names_.size(); ++i) entry->parser.DefineVar(names_[i], &values_[i]);
    entry->parser.SetExpr(text);
    // GetUsedVar parses with undefined names allowed, so it lists them too: that is how an
    // undeclared name is found and named (docs/guide/SCENE_FORMAT.md, "Errors": "name not
    // declared").
    for (const auto& [name, ptr] : entry->parser.GetUsedVar()) {
      auto it = std::find(names_.begin(), names_.end(), name);
      if (it == names_.end()) {
        const std::string number = NameProblem(name, text);
        throw InputError(file, field,
                         number.empty() ? "unknown parameter '" + name + "' in expression " +
                                              Quoted(text)
                                        : number);
      }
      entry->used.push_back(int(it - names_.begin()));
    }
    std::sort(entry->used.begin(), entry->used.end());
    // The first evaluation builds the byte code; later ones only run it.
    std::lock_guard lock(mutex_);
    entry->parser.Eval();
    if (entry->parser.GetNumResults() != 1)
      throw InputError(file, field,
                       "expression " + Quoted(text) + " has several comma-separated parts");
  } catch (const mu::Parser::exception_type& e) {
    throw InputError(file, field, "cannot parse expression " + Quoted(text) + ": " + e.GetMsg());
  }
  for (int p : entry->used) used_[size_t(p)] = true;
  entries_.push_back(std::move(entry));
  return int(entries_.size()) - 1;
}

double ExpressionTable::Evaluate(int id, const std::vector<double>& psi) const {
  if (id < 0 || id >= size()) throw std::out_of_range("ExpressionTable::Evaluate: bad id");
  if (psi.size() != names_.size())
    throw std::invalid_argument("ExpressionTable::Evaluate: Ψ has " + std::to_string(psi.size()) +
                                " values, the scene " + std::to_string(names_.size()) +
                                " parameters");
  std::lock_guard lock(mutex_);
  std::copy(psi.begin(), psi.end(), values_.get());
  try {
    return entries_[size_t(id)]->parser.Eval();
  } catch (const mu::Parser::exception_type&) {
    // Compiled expressions do not fail at run time (division by zero gives inf); a
    // numerical outcome is a value, not an exception (STYLE.md).
    return std::nan("");
  }
}

const std::string& ExpressionTable::Text(int id) const { return entries_.at(size_t(id))->text; }
const std::string& ExpressionTable::File(int id) const { return entries_.at(size_t(id))->file; }
const std::string& ExpressionTable::Field(int id) const {
  return entries_.at(size_t(id))->field;
}
const std::vector<int>& ExpressionTable::UsedParameters(int id) const {
  return entries_.at(size_t(id))->used;
}

double EvaluateConstantExpression(const std::string& text, const std::string& file,
                                  const std::string& field, const std::string& why_constant) {
  CheckForm(text, file, field);
  double value = 0.0;
  try {
    mu::Parser parser;
    parser.SetExpr(text);
    const auto& used = parser.GetUsedVar();
    if (!used.empty() && !NameProblem(used.begin()->first, text).empty())
      throw InputError(file, field, NameProblem(used.begin()->first, text));
    if (!used.empty())
      throw InputError(file, field,
                       "expression " + Quoted(text) + " reads '" + used.begin()->first +
                           "', but this value must be a constant (" + why_constant + ")");
    value = parser.Eval();
    if (parser.GetNumResults() != 1)
      throw InputError(file, field,
                       "expression " + Quoted(text) + " has several comma-separated parts");
  } catch (const mu::Parser::exception_type& e) {
    throw InputError(file, field, "cannot parse expression " + Quoted(text) + ": " + e.GetMsg());
  }
  if (!std::isfinite(value))
    throw InputError(file, field,
                     "expression " + Quoted(text) + " is not finite (" + std::to_string(value) +
                         ")");
  return value;
}

}  // namespace vkr
