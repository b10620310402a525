#pragma once
// The observer's eye a session stored: `[observer] age_years` and `pigmentation` of the resolved
// experiment in sessions.config (TOML), what the analytic glare models (Spencer 1995 Eq. 10,
// CIE 146:2002) were given. Sessions stored before these keys existed have none.
#include <optional>
#include <string>

namespace glarelab::analysis {

struct StoredObserverEye {
  double age_years = 0.0;
  double pigmentation = 0.0;
};

// The eye in a stored configuration, or nothing when the text is not TOML or lacks either key.
std::optional<StoredObserverEye> stored_observer_eye(const std::string& config_toml);

// For the report: "64.5 years, pigmentation 0.25", or "not stored".
std::string observer_eye_text(const std::string& config_toml);

}  // namespace glarelab::analysis
