#pragma once
// The straylight measurements of the loaded sessions for `glarelab analyze`: each session's
// stored answers replayed through its stored design as `run` and `run --resume` do
// (runner/session/straylight_session.h), handed to analysis/ as plain data
// (analysis/straylight_measurement.h), which may not build procedures.
#include <string>
#include <vector>

#include "analysis/loaded_database.h"
#include "analysis/straylight_measurement.h"

namespace glarelab {

// Every loaded session that measured straylight. A session whose answers cannot be replayed is
// left out with a note naming it and why, appended to `notes`.
std::vector<analysis::StraylightMeasurement> rebuild_straylight_measurements(const analysis::LoadedData& data,
                                                                             std::vector<std::string>& notes);

}  // namespace glarelab
