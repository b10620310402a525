// The one place that maps experiment.procedure to its implementation.
#include <stdexcept>

#include "protocols/adaptive_procedure.h"
#include "protocols/adjustment_procedure.h"
#include "protocols/fixed_design_procedure.h"
#include "protocols/forced_choice.h"
#include "protocols/procedure.h"
#include "protocols/rating_procedure.h"
#include "protocols/straylight_procedure.h"

namespace glarelab {

std::unique_ptr<Procedure> make_procedure(const Experiment& experiment,
                                          const std::map<std::string, double>& source_peak_cd_m2) {
  if (experiment.procedure == "forced_choice") {
    return make_forced_choice_procedure(experiment, source_peak_cd_m2);
  }
  if (experiment.procedure == "staircase" || experiment.procedure == "quest" || experiment.procedure == "quest_plus" ||
      experiment.procedure == "psi") {
    return std::make_unique<AdaptiveProcedure>(experiment, source_peak_cd_m2);
  }
  if (experiment.procedure == "rating") return make_rating_procedure(experiment);
  if (experiment.procedure == "adjustment") return make_adjustment_procedure(experiment, source_peak_cd_m2);
  if (experiment.procedure == "straylight") return std::make_unique<StraylightProcedure>(experiment.straylight, experiment.seed);
  throw std::invalid_argument("unknown procedure '" + experiment.procedure + "'");
}

}  // namespace glarelab
