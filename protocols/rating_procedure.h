#pragma once
// Likert ratings on named categories (Luidolt et al. 2020, section 7.2: glare appearance, glare
// movement, eye adaptation, visual acuity, scotopic vision, overall): every condition row's
// "scene" is shown alone, centred, once per category and repetition, in an order shuffled with
// the seed (stream trial_order). The answer is the number 1..scale_points; no answer is right.
// A row whose scene is a physical object ("real:desk lamp", core/real_stimulus.h) is rated the
// same way; its trials carry the object's name (TrialPlan::real_stimulus) and their condition
// JSON "stimulus": "real".
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "protocols/experiment.h"
#include "protocols/procedure.h"
#include "protocols/toml_table_reader.h"

namespace glarelab {

// Reads categories, scale_points, scale_anchors and repetitions of [procedure] (type = "rating").
void read_rating_procedure(TableReader& procedure, Experiment& experiment);

// The question of a category: "Rate the overall from 1 to 7", or with anchors "Rate the overall
// from 1 (completely different) to 7 (exactly the same)".
std::string rating_question(const RatingSpec& spec, const std::string& category);

std::vector<TrialPlan> build_rating_trials(const Experiment& experiment);

std::unique_ptr<Procedure> make_rating_procedure(const Experiment& experiment);

}  // namespace glarelab
