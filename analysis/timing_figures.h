#pragma once
// The timing section's figures (analysis/timing_quality.h): the response-time histogram (when any
// trial has a response time) and, per `glarelab timing-test` session, the flip-interval histogram
// and the flip intervals in flip order with the missed deadlines marked (as Psychtoolbox's
// VBLSyncTest plots them: docs/TIMING.md).
#include <vector>

#include "analysis/analysis_report.h"

namespace glarelab::analysis {

std::vector<Figure> timing_figures(const TimingQuality& timing);

}  // namespace glarelab::analysis
