#pragma once
// Bad user input. The command line prints what() as one line and exits with status 2
// (docs/guide/SCENE_FORMAT.md, "Errors": bad input never crashes); library code throws it and never
// exits.

#include <stdexcept>
#include <string>

namespace vkr {

class InputError : public std::runtime_error {
 public:
  // file: the file at fault (scene, camera, image, mesh). field: where inside it, as a
  // dotted JSON path with indices ("nodes[2].transforms[0].rotate[1]"); empty when the
  // whole file is at fault. problem: what is wrong, in plain words.
  InputError(std::string file, std::string field, std::string problem);

  const std::string& file() const { return file_; }
  const std::string& field() const { return field_; }
  const std::string& problem() const { return problem_; }

 private:
  std::string file_, field_, problem_;
};

}  // namespace vkr
