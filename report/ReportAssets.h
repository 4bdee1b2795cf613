#pragma once
// What report.html is made of besides its layout (report/Report.cpp): images as data URIs
// within a size budget, the chain as compact JSON for the plots, the JavaScript libraries
// read from Debian's packages. The page's own style and scripts are files beside this one
// (page.css, error_hook.js, page.js, model_view.js), embedded at build time.

#include <filesystem>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

namespace vkr::report {

std::string Base64(const std::string& bytes);
// Escapes &, <, >, " for HTML text and attribute values.
std::string Html(const std::string& text);

// A JPEG data URI of the image file, its longest side at most `max_side` pixels (box
// filtered), quality 85; nothing when the file is missing or unreadable. JPEG: the
// reprojections of noisy photographs are four times smaller than as PNG, which keeps a
// report of a dozen cameras under its budget.
std::optional<std::string> ImageDataUri(const std::filesystem::path& file, int max_side);

// chain.csv as {"names": [...], "chains": [{"iteration": [...], "level": [...],
// "temperature": [...], "accepted": [...], "swapped": [...], "log_posterior": [...],
// "values": [[per parameter]...]}...]}, each chain thinned to at most `max_rows` rows; a
// kept row's accepted/swapped are the shares over the rows it stands for. Throws InputError
// naming the file when it is missing or malformed.
nlohmann::json ReadChain(const std::filesystem::path& file, int max_rows = 1000);

// One JavaScript library file's text, or nothing when it is not installed.
std::optional<std::string> ReadLibrary(const std::filesystem::path& file);

}  // namespace vkr::report
