#include "recon/AtomicWrite.h"

#include <fstream>
#include <stdexcept>

namespace fs = std::filesystem;

namespace vkr::recon {

void WriteAtomically(const fs::path& file, const std::string& text) {
  const fs::path tmp = file.string() + ".tmp";
  {
    std::ofstream out(tmp, std::ios::binary);
    out << text;
    if (!out) throw std::runtime_error("cannot write " + tmp.string());
  }
  fs::rename(tmp, file);
}

void WritePngAtomically(const fs::path& file, const Image& image) {
  const fs::path tmp = file.parent_path() / (file.stem().string() + ".tmp.png");
  WritePng(tmp, image);
  fs::rename(tmp, file);
}

}  // namespace vkr::recon
