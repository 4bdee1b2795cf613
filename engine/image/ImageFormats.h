#pragma once
// Internal to vkr_image: one reader/writer per file family, behind the public Image.h API.
// ImageIo.cpp opens the file, sniffs its magic bytes and dispatches here, so each family
// only ever sees files that claim to be of its kind.

#include <cstdint>
#include <filesystem>
#include <span>
#include <string>

#include "engine/image/Image.h"

namespace vkr::image_detail {

// Throws InputError(file, "", problem). One place, so every message names the path the same
// way.
[[noreturn]] void Fail(const std::filesystem::path& file, const std::string& problem);

// A larger image is a corrupt or hostile header, not a photograph; refusing it keeps a bad
// file from turning into std::bad_alloc or an int overflow. (2^28 pixels = 4 GiB as RGBA.)
constexpr long long kMaxPixels = 1LL << 28;

// --- OpenEXR (ExrIo.cpp) ---
// True when the bytes start with OpenEXR's magic number.
bool IsExr(std::span<const uint8_t> head);
// Reads R, G, B and (optional) A of the data window as linear values and returns them
// sRGB-encoded (Image.h colour convention); a file with only Y is read as grey.
Image LoadExr(const std::filesystem::path& file);
// Size of the data window, from the header only.
void ReadExrSize(const std::filesystem::path& file, int* width, int* height);

// --- Netpbm PGM/PPM (PnmIo.cpp) ---
// True for "P2", "P3", "P5", "P6" (grey or colour, ASCII or binary).
bool IsPnm(std::span<const uint8_t> head);
// Decodes a whole PGM/PPM file held in memory. Values are scaled by the header's maxval,
// so a 16-bit or maxval-1023 file reads the same as its 8-bit version.
Image DecodePnm(const std::filesystem::path& file, std::span<const uint8_t> bytes);
// Size from the header; `head` must hold at least the header (a few hundred bytes).
void ReadPnmSize(const std::filesystem::path& file, std::span<const uint8_t> head, int* width,
                 int* height);

}  // namespace vkr::image_detail
