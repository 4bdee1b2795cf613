#include "report/ReportAssets.h"

#include <stb/stb_image_write.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <locale>
#include <sstream>

#include "engine/common/InputError.h"
#include "engine/image/Image.h"
#include "engine/image/Pyramid.h"

namespace fs = std::filesystem;

namespace vkr::report {
namespace {

void Append(void* context, void* data, int size) {
  static_cast<std::string*>(context)->append(static_cast<const char*>(data), size_t(size));
}

}  // namespace

std::string Base64(const std::string& bytes) {
  static const char* kAlphabet = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  out.reserve((bytes.size() + 2) / 3 * 4);
  for (size_t i = 0; i < bytes.size(); i += 3) {
    const unsigned b0 = static_cast<unsigned char>(bytes[i]);
    const unsigned b1 = i + 1 < bytes.size() ? static_cast<unsigned char>(bytes[i + 1]) : 0u;
    const unsigned b2 = i + 2 < bytes.size() ? static_cast<unsigned char>(bytes[i + 2]) : 0u;
    const unsigned v = (b0 << 16) | (b1 << 8) | b2;
    out += kAlphabet[(v >> 18) & 63];
    out += kAlphabet[(v >> 12) & 63];
    out += i + 1 < bytes.size() ? kAlphabet[(v >> 6) & 63] : '=';
    out += i + 2 < bytes.size() ? kAlphabet[v & 63] : '=';
  }
  return out;
}

std::string Html(const std::string& text) {
  std::string out;
  for (char c : text) {
    switch (c) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      default: out += c;
    }
  }
  return out;
}

std::optional<std::string> ImageDataUri(const fs::path& file, int max_side) {
  if (!fs::is_regular_file(file)) return std::nullopt;
  Image image;
  try {
    image = LoadImage(file);
  } catch (const std::exception&) {
    return std::nullopt;
  }
  const int side = std::max(image.width, image.height);
  image = BoxShrink(image, (side + max_side - 1) / max_side);
  std::vector<unsigned char> rgb(size_t(image.width) * image.height * 3);
  for (size_t i = 0, n = size_t(image.width) * image.height; i < n; ++i)
    for (size_t c = 0; c < 3; ++c)
      rgb[i * 3 + c] = static_cast<unsigned char>(std::lround(std::clamp(image.rgba[i * 4 + c], 0.0f, 1.0f) * 255.0f));
  std::string jpeg;
  if (!stbi_write_jpg_to_func(&Append, &jpeg, image.width, image.height, 3, rgb.data(), 85)) return std::nullopt;
  return "data:image/jpeg;base64," + Base64(jpeg);
}

nlohmann::json ReadChain(const fs::path& file, int max_rows) {
  std::ifstream in(file);
  if (!in) throw InputError(file.string(), "", "missing or unreadable (a run writes it with map.json)");
  std::string line;
  if (!std::getline(in, line)) throw InputError(file.string(), "", "empty: no header line");
  std::vector<std::string> columns;
  {
    std::stringstream header(line);
    for (std::string c; std::getline(header, c, ',');) columns.push_back(c);
  }
  const std::vector<std::string> fixed = {"iteration", "chain", "level", "temperature", "accepted",
                                          "swapped", "log_posterior", "log_likelihood", "log_prior"};
  if (columns.size() < fixed.size() || !std::equal(fixed.begin(), fixed.end(), columns.begin()))
    throw InputError(file.string(), "", "the header is not iteration,chain,level,temperature,accepted,swapped,"
                                        "log_posterior,log_likelihood,log_prior,<parameters...>");
  const size_t params = columns.size() - fixed.size();
  std::vector<std::vector<std::vector<double>>> rows;  // per chain, per row, the columns
  for (int number = 2; std::getline(in, line); ++number) {
    if (line.empty()) continue;
    std::istringstream cells(line);
    cells.imbue(std::locale::classic());
    std::vector<double> row;
    for (std::string cell; std::getline(cells, cell, ',');) {
      std::istringstream value(cell);
      value.imbue(std::locale::classic());
      double v = NAN;
      if (cell != "nan" && cell != "-nan" && !(value >> v))
        throw InputError(file.string(), "line " + std::to_string(number), "'" + cell + "' is not a number");
      row.push_back(v);
    }
    if (row.size() != columns.size())
      throw InputError(file.string(), "line " + std::to_string(number),
                       std::to_string(row.size()) + " values, the header names " + std::to_string(columns.size()));
    const int chain = int(row[1]);
    if (chain < 0 || chain > 1000) throw InputError(file.string(), "line " + std::to_string(number), "bad chain index");
    if (size_t(chain) >= rows.size()) rows.resize(size_t(chain) + 1);
    rows[size_t(chain)].push_back(std::move(row));
  }
  nlohmann::json chains = nlohmann::json::array();
  for (const auto& chain : rows) {
    const size_t stride = std::max<size_t>(1, (chain.size() + size_t(max_rows) - 1) / size_t(max_rows));
    nlohmann::json c = {{"iteration", nlohmann::json::array()}, {"level", nlohmann::json::array()},
                        {"temperature", nlohmann::json::array()}, {"accepted", nlohmann::json::array()},
                        {"swapped", nlohmann::json::array()}, {"log_posterior", nlohmann::json::array()},
                        {"values", nlohmann::json::array()}};
    for (size_t p = 0; p < params; ++p) c["values"].push_back(nlohmann::json::array());
    // Floats: seven digits are plenty for a plot and halve the page's data.
    auto number = [](double v) { return std::isfinite(v) ? nlohmann::json(float(v)) : nlohmann::json(nullptr); };
    for (size_t start = 0; start < chain.size(); start += stride) {
      const size_t end = std::min(chain.size(), start + stride);
      double accepted = 0.0, swapped = 0.0;
      for (size_t r = start; r < end; ++r) accepted += chain[r][4], swapped += chain[r][5];
      const std::vector<double>& row = chain[start];
      c["iteration"].push_back(int(row[0]));
      c["level"].push_back(int(row[2]));
      c["temperature"].push_back(number(row[3]));
      c["accepted"].push_back(number(accepted / double(end - start)));
      c["swapped"].push_back(number(swapped / double(end - start)));
      c["log_posterior"].push_back(number(row[6]));
      for (size_t p = 0; p < params; ++p) c["values"][p].push_back(number(row[fixed.size() + p]));
    }
    chains.push_back(std::move(c));
  }
  return {{"names", std::vector<std::string>(columns.begin() + long(fixed.size()), columns.end())}, {"chains", chains}};
}

std::optional<std::string> ReadLibrary(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  if (!in) return std::nullopt;
  std::ostringstream text;
  text << in.rdbuf();
  std::string s = text.str();
  // Inside <script>, only "</script" ends the element; written as "<\/script" it means the same to JavaScript.
  for (size_t at = 0; (at = s.find("</script", at)) != std::string::npos;) s.replace(at, 2, "<\\/"), at += 3;
  return s;
}

}  // namespace vkr::report
