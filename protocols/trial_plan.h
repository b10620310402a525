#pragma once
// What one trial shows and accepts, decided before it runs, and what came of it.
#include <optional>
#include <string>
#include <vector>

namespace glarelab {

struct TrialPlan {
  int trial_index = 0;  // from 0 within the session
  int block = 0;
  std::string procedure;       // forced_choice | staircase | quest | adjustment | rating
  std::string condition_name;
  std::string condition_json;  // the condition row plus presentation facts, as a JSON object
  std::vector<std::string> positions;  // e.g. {"left", "right"}
  std::vector<std::string> scenes;     // scene name shown at each position
  // Peak luminance (cd/m2) of the source at each position: what a simulated observer compares.
  std::vector<double> source_luminance_cd_m2;
  std::vector<std::string> allowed_responses;
  std::string correct_response;  // empty when no answer is right (equal sources)
  std::optional<double> intensity;
  std::string question;
  int stimulus_frames = 1;
};

struct Response {
  std::string value;               // one of allowed_responses, or "abort"
  std::optional<double> response_time_s;  // from the onset flip
};

struct TrialOutcome {
  std::string response;
  std::optional<int> correct;
};

}  // namespace glarelab
