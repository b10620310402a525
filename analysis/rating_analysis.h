#pragma once
// Ratings (Luidolt 2020, section 7.2.1, Figs. 7.1-7.7): how many answers fell on each point of
// the scale, their mean and median, per condition and per condition x category (the question a
// trial asked: the `category` key of its condition record, protocols/rating_procedure.cpp), and
// per category a rank test across the conditions on paired ratings (same participant, same
// category): the Wilcoxon signed-rank test for two conditions, the Friedman test and Kendall's W
// for more (analysis/rank_tests.h).
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "analysis/loaded_database.h"
#include "analysis/rank_tests.h"
#include "analysis/rating_post_hoc.h"

namespace glarelab::analysis {

struct RatingDistribution {
  std::string condition;
  std::string category;  // the question; empty in RatingAnalysis::conditions (every category pooled)
  // Answer value -> number of answers (the response's own categories, not the question's):
  // numeric answers in numeric order, with every point of the stored scale (1..scale_points)
  // listed in `cells` even when nobody chose it.
  std::vector<std::pair<std::string, long>> categories;
  long answers = 0;
  std::optional<double> mean;    // when every answer is a number
  std::optional<double> median;
};

// The rank test of one category across its conditions.
struct RatingComparison {
  std::string category;
  std::vector<std::string> conditions;  // in the stored design's order; the columns of `scores`
  // Participants (participant code) who rated every condition of the category, and their score
  // per condition: the mean of their ratings of it (one rating per cell without repetitions).
  std::vector<std::string> participants;
  std::vector<std::vector<double>> scores;  // [participant][condition]
  std::vector<std::string> left_out;        // participants without a rating of every condition
  std::optional<WilcoxonSignedRank> wilcoxon;  // two conditions: conditions[0] - conditions[1]
  std::optional<FriedmanTest> friedman;        // three or more
  // After a Friedman p <= 0.05: every pair's signed-rank test, Holm-adjusted (rating_post_hoc.h).
  std::vector<RatingPairTest> post_hoc;
  std::string unavailable;                     // non-empty: why neither test was run
};

struct RatingAnalysis {
  std::vector<RatingDistribution> conditions;  // per condition, categories pooled
  // Categories and conditions in the order of the stored design (the experiment file's), those it
  // does not name after them in order of first appearance.
  std::vector<RatingDistribution> cells;       // per category x condition
  std::vector<std::string> category_order;     // "" when trials name no category
  std::vector<std::string> scale;              // every answer value, in order (the figures' segments)
  std::vector<RatingComparison> comparisons;   // per category, when every answer is a number
  std::vector<std::string> notes;
  long trials = 0;
  bool empty() const { return trials == 0; }
};

// What a session's stored configuration (sessions.config) says of a rating design: the scale's
// points (`[procedure] scale_points`, 0 when absent), the categories in the order of `[procedure]
// categories` and the conditions in the order of the `[[conditions.rows]]` names. Empty when the
// text is not TOML or lacks the keys (the analysis then orders by first appearance).
struct StoredRatingDesign {
  int scale_points = 0;
  std::vector<std::string> categories;
  std::vector<std::string> conditions;
};
StoredRatingDesign stored_rating_design(const std::string& config_toml);

RatingAnalysis analyse_ratings(const LoadedData& data);

}  // namespace glarelab::analysis
