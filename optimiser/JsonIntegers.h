#pragma once
// Integers read from the files a run saves (checkpoints, start_search.json), strictly: the
// checkpoint reader and the reconstruction's resume both use them.

#include <cstdint>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace vkr::opt {

// An integer of a saved file (checkpoint, start_search.json): a JSON integer within T's
// range, else std::invalid_argument. nlohmann's get<int> would cast a float, undefined
// beyond int's range (fuzz_checkpoint found target_levels 2.6e51), and wrap an integer that
// does not fit.
template <typename T>
T ReadInteger(const nlohmann::json& j) {
  if (j.is_number_unsigned()) {
    if (j.get<uint64_t>() <= uint64_t(std::numeric_limits<T>::max())) return T(j.get<uint64_t>());
  } else if (j.is_number_integer()) {
    const int64_t v = j.get<int64_t>();
    if (v >= int64_t(std::numeric_limits<T>::min()) && v <= int64_t(std::numeric_limits<T>::max())) return T(v);
  }
  throw std::invalid_argument("expected an integer from " + std::to_string(std::numeric_limits<T>::min()) + " to " +
                              std::to_string(std::numeric_limits<T>::max()) + ", found " + j.dump());
}

template <typename T>
std::vector<T> ReadIntegers(const nlohmann::json& j) {
  if (!j.is_array()) throw std::invalid_argument("expected a list of integers, found " + j.dump());
  std::vector<T> v;
  for (const nlohmann::json& x : j) v.push_back(ReadInteger<T>(x));
  return v;
}

}  // namespace vkr::opt
