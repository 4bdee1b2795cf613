#pragma once
// Files a run writes while it may be killed: written whole or not at all, through a
// temporary file and a rename, so that a run killed mid-write leaves the previous file (a
// checkpoint, map.json) intact.

#include <filesystem>
#include <string>

#include "engine/image/Image.h"

namespace vkr::recon {

void WriteAtomically(const std::filesystem::path& file, const std::string& text);
void WritePngAtomically(const std::filesystem::path& file, const Image& image);

}  // namespace vkr::recon
