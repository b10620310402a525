#pragma once
// The ratings analysis (analysis/rating_analysis.h) in the report: the HTML section's tables and
// test sentences, the terminal lines, and the ratings' CSV files.
#include <string>

#include "analysis/rating_analysis.h"

namespace glarelab::analysis {

// The section's heading, explanation, tables and test sentences (figures are added by the caller).
std::string ratings_html(const RatingAnalysis& ratings);

// One "rating ..." line per condition, one "rating test ..." per category and one "rating post
// hoc ..." per pair tested after it.
std::string ratings_terminal(const RatingAnalysis& ratings);

// ratings.csv: one row per category x condition: counts per answer value (`answers_<value>`,
// characters outside [A-Za-z0-9_] as '_'), mean and median.
std::string ratings_csv(const RatingAnalysis& ratings);

// rating_tests.csv: one row per category: the test run, on how many participants, its numbers
// (empty where they do not apply) or why it was not computed.
std::string rating_tests_csv(const RatingAnalysis& ratings);

// rating_post_hoc.csv: a row per pair of conditions of each category whose Friedman test was
// significant (the caller writes it only when there is one).
std::string rating_post_hoc_csv(const RatingAnalysis& ratings);

}  // namespace glarelab::analysis
