#pragma once
// Ratings (Luidolt et al., Figs. 7.1-7.7): per condition, how many answers fell in each
// category, and, when every answer is a number, their mean and median.
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "analysis/loaded_database.h"

namespace glarelab::analysis {

struct RatingDistribution {
  std::string condition;
  std::vector<std::pair<std::string, long>> categories;  // numeric categories in numeric order
  long answers = 0;
  std::optional<double> mean;
  std::optional<double> median;
};

struct RatingAnalysis {
  std::vector<RatingDistribution> conditions;
  long trials = 0;
  bool empty() const { return trials == 0; }
};

RatingAnalysis analyse_ratings(const LoadedData& data);

}  // namespace glarelab::analysis
