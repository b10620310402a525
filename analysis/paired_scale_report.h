#pragma once
// The Bradley-Terry scales of pairwise designs (analysis/paired_scale.h) as report HTML.
#include <string>
#include <vector>

#include "analysis/paired_scale.h"

namespace glarelab::analysis {

// A paragraph and one table per pooled group: option, log worth, SE, 95 % interval, worth.
std::string paired_scales_html(const std::vector<PairedScale>& scales);

}  // namespace glarelab::analysis
