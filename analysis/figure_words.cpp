#include "analysis/figure_words.h"

#include <algorithm>

namespace glarelab::analysis {

const std::string& FigureWords::display(const std::string& name) const {
  const auto found = names.find(name);
  return found == names.end() ? name : found->second;
}

std::string column_words(const std::string& column) {
  std::string words = column;
  std::replace(words.begin(), words.end(), '_', ' ');
  return words;
}

}  // namespace glarelab::analysis
