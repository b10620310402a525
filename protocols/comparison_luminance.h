#pragma once
// A trial as it would be shown with its comparison at other luminances: a staircase or QUEST trial
// at a given intensity, an adjustment trial with its spots at given settings. glarelab render uses
// it to preview any point of an adaptive track or an adjustment, not only where the procedure
// starts.
#include <vector>

#include "protocols/trial_plan.h"

namespace glarelab {

// `luminance_cd_m2`: one value per comparison position (TrialPlan::comparison_positions), each the
// peak luminance that position's scene is scaled to. The plan's scales, source luminances,
// intensity (adaptive) or start settings (adjustment) and correct answer follow. Throws
// std::invalid_argument when the plan has no comparison (fixed designs), when the count differs,
// or for a luminance that is not finite and positive.
TrialPlan with_comparison_luminance(TrialPlan plan, const std::vector<double>& luminance_cd_m2);

}  // namespace glarelab
