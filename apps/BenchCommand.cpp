// Placeholder while `vkrecon bench` is being written (issue 6); replaced by its real parser.
#include <iostream>

#include "apps/Commands.h"

namespace vkr::app {

int RunBench(int, char**) {
  std::cerr << "vkrecon bench: not built yet\n";
  return 1;
}

}  // namespace vkr::app
