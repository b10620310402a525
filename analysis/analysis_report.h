#pragma once
// Everything `glarelab analyze` computes from loaded databases: one analysis per procedure
// found, timing and tracker quality, and the figures (SVG) that go into the report.
#include <cstdint>
#include <string>
#include <vector>

#include "analysis/adjustment_analysis.h"
#include "analysis/figure_words.h"
#include "analysis/forced_choice_analysis.h"
#include "analysis/graded_choice_analysis.h"
#include "analysis/loaded_database.h"
#include "analysis/paired_scale.h"
#include "analysis/pse_analysis.h"
#include "analysis/quest_plus_posterior.h"
#include "analysis/rating_analysis.h"
#include "analysis/staircase_analysis.h"
#include "analysis/straylight_measurement.h"
#include "analysis/timing_quality.h"
#include "analysis/tracker_quality.h"

namespace glarelab::analysis {

struct AnalysisOptions {
  int bootstrap_samples = 200;  // per psychometric fit
  int last_reversals = 6;       // staircase threshold: mean of the last k reversals
  std::uint64_t seed = 1;       // bootstrap draws
  unsigned threads = 0;         // psychometric fit threads; 0: one per hardware thread
  FigureWords words;            // the figures' axis words and display names ([analysis] table)
};

struct Figure {
  std::string file_stem;  // "staircase_1" -> figures/staircase_1.svg
  std::string section;    // forced_choice | graded_choice | staircase | quest_plus | straylight | adjustment | rating | timing | tracker
  std::string caption;
  std::string svg;
};

struct AnalysisReport {
  LoadedData data;
  AnalysisOptions options;
  ForcedChoiceAnalysis forced_choice;  // pair preferences of the trials without a graded variable
  std::vector<PairedScale> paired_scales;  // Bradley-Terry per pooled forced-choice group (3+ options)
  GradedChoiceAnalysis graded_choice;  // forced choice with a graded variable, per glare group
  std::vector<StaircaseResult> staircases;
  PseAnalysis pse;  // PSE staircases (response_rule = "pse")
  std::vector<QuestPlusPosterior> quest_plus;  // final posterior per QUEST+ / Psi track
  std::vector<StraylightMeasurement> straylight;  // per straylight session
  AdjustmentAnalysis adjustments;
  RatingAnalysis ratings;
  TimingQuality timing;
  TrackerQuality tracker;
  std::vector<Figure> figures;
};

AnalysisReport analyse(LoadedData data, const AnalysisOptions& options);

// The final posteriors of the QUEST+ / Psi tracks, rebuilt by the runner (which alone may build a
// procedure: runner/cli/quest_plus_posteriors.h), stored in the report with one figure per track
// and parameter (section "quest_plus").
void add_quest_plus_posteriors(AnalysisReport& report, std::vector<QuestPlusPosterior> posteriors);

// The straylight measurements, estimated by the runner (which alone may build the procedure:
// runner/cli/straylight_measurements.h), stored in the report with one likelihood figure each
// (section "straylight").
void add_straylight_measurements(AnalysisReport& report, std::vector<StraylightMeasurement> measurements);

// The figures of a report (called by analyse; separate so the drawing is one concept).
std::vector<Figure> draw_figures(const AnalysisReport& report);

}  // namespace glarelab::analysis
