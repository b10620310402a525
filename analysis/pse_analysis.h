#pragma once
// Points of subjective equality from PSE staircases (response_rule = "pse"; Spencer et al. 1995,
// section 4): per participant (session) and track, the comparison luminance that looks as bright
// as the reference, as a fraction of the display's peak, and per group (block) and glare strength
// the mean over participants: the data of Spencer's Figs. 12-13 (perceived intensity against
// glare strength).
//
// The PSE is the threshold (F = 1/2) of psignifit 4's posterior (analysis/psignifit_pse.h:
// cumulative normal, no guess or lapse rate, overdispersion free) over every trial of the track
// whose answer named a side, with the central 95 % of the threshold's marginal. Why a posterior
// over all the trials and not the mean of reversals: it uses every answer instead of the few at
// reversals, does not depend on the last step size, and has no separation problem (a short track
// whose answers separate perfectly has no maximum-likelihood fit, but a posterior, the width
// prior bounding the slope). Why leave "neither" out: with a neither band symmetric about
// equality, P(comparison brighter | a side was named) is exactly 1/2 at the PSE whatever the
// band's width, while counting "neither" as either side would shift it. The mean of the last k
// reversals is reported beside it as a second opinion, and stands in for the PSE (marked so) only
// when no function can be fitted (fewer than two comparison levels answered).
#include <optional>
#include <string>
#include <vector>

#include "analysis/loaded_database.h"
#include "analysis/psignifit_pse.h"
#include "analysis/psychometric_fit.h"

namespace glarelab::analysis {

struct PseTrack {
  std::string participant_label;
  std::string name;   // the track (staircase) name
  std::string group;  // its block's name; empty without blocks
  double glare_gain = 1.0;  // the reference's glare gain (the row's glare_gain, 1 without it; 0 for control glare)
  double reference_fraction = 0.0;  // the reference's peak / the display's peak
  int trials = 0;           // answered trials
  int neither = 0;          // of which "neither"
  std::optional<double> pse_fraction;     // the posterior's MAP threshold (else the reversal mean) / display peak
  std::optional<Interval> pse_interval;   // its central 95 % credible interval (none from reversals)
  bool pse_from_reversals = false;        // no function could be fitted: pse_fraction is the reversal mean
  std::optional<double> reversal_mean_fraction;  // mean of the last k reversals / display peak
  int reversals_used = 0;
  std::string note;  // why there is no fitted PSE, when there is none
  std::optional<PsignifitPse> fit;  // on the fraction-of-peak axis
};

// One point of the figure: a group at one glare gain, over the participants whose track gave a PSE.
struct PsePoint {
  std::string group;
  double glare_gain = 0.0;
  double mean_pse_fraction = 0.0;
  // One participant: the credible interval of that PSE; several: mean +- t(0.975, n-1) SE.
  std::optional<Interval> interval;
  int participants = 0;
};

struct PseAnalysis {
  std::vector<PseTrack> tracks;
  std::vector<PsePoint> points;     // by group, then glare gain
  std::optional<double> reference_fraction;  // the reference's level (Spencer: 0.75), when all tracks agree
};

struct PseOptions {
  int last_reversals = 6;
  unsigned threads = 0;
};

// True for a trial of a PSE staircase.
bool is_pse_trial(const LoadedTrial& trial);

PseAnalysis analyse_pse(const LoadedData& data, const PseOptions& options);

}  // namespace glarelab::analysis
