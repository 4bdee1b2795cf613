#include "engine/common/InputError.h"

namespace vkr {
namespace {

std::string Compose(const std::string& file, const std::string& field,
                    const std::string& problem) {
  // A command-line option has no file: "--sweep: …" rather than a placeholder.
  std::string line = file;
  if (!field.empty()) line += (line.empty() ? "" : ": ") + field;
  line += (line.empty() ? "" : ": ") + problem;
  // One line, always: a multi-line library message would break the exit-2 contract.
  for (char& c : line)
    if (c == '\n' || c == '\r') c = ' ';
  return line;
}

}  // namespace

InputError::InputError(std::string file, std::string field, std::string problem)
    : std::runtime_error(Compose(file, field, problem)),
      file_(std::move(file)),
      field_(std::move(field)),
      problem_(std::move(problem)) {}

}  // namespace vkr
