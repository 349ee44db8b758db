// The Levenshtein distance between two names, for suggesting a name close to
// a wrong one (urdf_loader.cpp) and for spotting a misspelled joint column
// (read_samples.hpp, hold_unlogged_joints).
#pragma once

#include <algorithm>
#include <cstddef>
#include <string_view>
#include <vector>

namespace massid::detail {

inline std::size_t edit_distance(std::string_view a, std::string_view b) {
  std::vector<std::size_t> row(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    std::size_t diagonal = row[0];
    row[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const std::size_t up = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (a[i - 1] != b[j - 1] ? 1 : 0)});
      diagonal = up;
    }
  }
  return row[b.size()];
}

}  // namespace massid::detail
