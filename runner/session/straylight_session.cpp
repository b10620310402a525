#include "runner/session/straylight_session.h"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <stdexcept>
#include <numbers>

#include "glare/analytic/analytic_psf.h"
#include "glare/analytic/cie_glare_spread.h"
#include "glare/analytic/ring_straylight.h"
#include "protocols/straylight_model.h"
#include "protocols/straylight_procedure.h"

namespace glarelab {
namespace {

// An image size of the display's parity that holds a disc of `radius_px` about its centre, so that
// the image centred on the display has the display's centre as its own.
int centred_size_px(int display_px, double radius_px) {
  int size = 2 * static_cast<int>(std::ceil(radius_px)) + 2;
  if ((display_px - size) % 2 != 0) ++size;
  return size;
}

}  // namespace

StraylightImages straylight_images(const DisplaySpec& display, const StraylightSpec& spec) {
  const auto radius_mm = [&](double angle_deg) {
    return display.viewing_distance_mm * std::tan(angle_deg * std::numbers::pi / 180.0);
  };
  const double outer_px = radius_mm(spec.ring_outer_deg) / display.pixel_pitch_mm;
  const int width = centred_size_px(display.width_px, outer_px), height = centred_size_px(display.height_px, outer_px);
  StraylightImages images{ImageRGBA(width, height, 0.0f), ImageRGBA(width, height, 0.0f), ImageRGBA(width, height, 0.0f)};
  for (ImageRGBA* image : {&images.ring, &images.left_half, &images.right_half})
    for (std::size_t i = 3; i < image->rgba.size(); i += 4) image->rgba[i] = 1.0f;
  const double inner_mm = radius_mm(spec.ring_inner_deg), outer_mm = radius_mm(spec.ring_outer_deg);
  const double field_mm = radius_mm(spec.test_field_radius_deg);
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      // Pixel centres from the image's (and the display's) centre, in mm on the screen.
      const double dx_mm = (x + 0.5 - 0.5 * width) * display.pixel_pitch_mm;
      const double dy_mm = (y + 0.5 - 0.5 * height) * display.pixel_pitch_mm;
      const double r_mm = std::hypot(dx_mm, dy_mm);
      ImageRGBA* lit = nullptr;
      if (r_mm >= inner_mm && r_mm < outer_mm) lit = &images.ring;
      else if (r_mm < field_mm && dx_mm < 0.0) lit = &images.left_half;
      else if (r_mm < field_mm && dx_mm > 0.0) lit = &images.right_half;
      if (lit == nullptr) continue;
      float* pixel = lit->pixel(x, y);
      pixel[0] = pixel[1] = pixel[2] = 1.0f;
    }
  }
  return images;
}

bool straylight_ring_on(int frame_in_interval, int frames_per_cycle) {
  return frame_in_interval % frames_per_cycle < frames_per_cycle / 2;
}

StraylightObserverEye simulated_straylight_eye(const Experiment& experiment) {
  const ObserverEye& eye = experiment.glare.observer_eye;
  const double factor = eye.straylight_log_s ? cie146_factor_for_straylight(*eye.straylight_log_s,
                                                                            kStraylightReferenceAngleDeg, eye.pigmentation)
                                             : cie146_age_factor(eye.age_years);
  StraylightObserverEye observer;
  observer.ring_veil_fraction = cie146_ring_veil_fraction(experiment.straylight.ring_inner_deg,
                                                          experiment.straylight.ring_outer_deg, factor, eye.pigmentation);
  return observer;
}

double simulated_straylight_log_s(const Experiment& experiment) {
  const StraylightSpec& spec = experiment.straylight;
  return std::log10(simulated_straylight_eye(experiment).ring_veil_fraction /
                    ring_straylight_constant(spec.ring_inner_deg, spec.ring_outer_deg));
}

std::unique_ptr<Observer> make_simulated_straylight_participant(const Experiment& experiment) {
  return make_straylight_participant(simulated_straylight_eye(experiment), experiment.seed,
                                     experiment.simulated_observer.response_time_median_s);
}

std::optional<StoredStraylight> stored_straylight(const ResultStore& store, std::int64_t session_id) {
  const std::optional<SessionRecord> session = store.load_session(session_id);
  if (!session) return std::nullopt;
  return replay_straylight(*session, store.load_trials(session_id), store.path());
}

std::optional<StoredStraylight> replay_straylight(const SessionRecord& session, const std::vector<TrialRecord>& trials,
                                                  const std::string& db_path) {
  const std::int64_t session_id = session.id;
  if (trials.empty() || trials.front().procedure != "straylight") return std::nullopt;
  const Experiment experiment = parse_experiment_text(session.config, "<session " + std::to_string(session_id) + " config>", "/");
  if (experiment.procedure != "straylight") return std::nullopt;
  StraylightProcedure procedure(experiment.straylight, experiment.seed);
  for (const TrialRecord& trial : trials) {
    if (procedure.finished()) break;
    const TrialPlan plan = procedure.next_trial();
    if (plan.condition_json != trial.condition)
      throw StoreError("SQLite: " + db_path + ": session " + std::to_string(session_id) + " trial " +
                       std::to_string(trial.trial_index) + " does not match its replay (stored condition " +
                       trial.condition + ", replayed " + plan.condition_json + ")");
    procedure.record_response(plan, Response{trial.response, trial.response_time_s});
  }
  if (procedure.answers().empty()) return std::nullopt;
  StoredStraylight stored;
  stored.session_id = session_id;
  stored.participant = session.participant;
  stored.eye = experiment.straylight.eye;
  stored.status = session.status;
  stored.age_years = experiment.glare.observer_eye.age_years;
  stored.answers = static_cast<int>(procedure.answers().size());
  stored.estimate = procedure.estimate();
  return stored;
}

std::string describe_straylight_session(const ResultStore& store, std::int64_t session_id) {
  const std::optional<StoredStraylight> stored = stored_straylight(store, session_id);
  if (!stored) return "";
  char line[320];
  std::snprintf(line, sizeof line,
                "  straylight, %s eye, %d answers: log(s) = %.2f, ESD %.3f (%s); age norm %.2f (population SD %.2f) "
                "at %.0f years\n",
                stored->eye.c_str(), stored->answers, stored->estimate.log_s, stored->estimate.esd_log10,
                stored->estimate.unreliable ? "unreliable: a spread of its likelihood above 0.08" : "reliable",
                straylight_age_norm_log10(stored->age_years), kStraylightAgeNormSdLog10, stored->age_years);
  return line;
}

std::string take_measured_straylight(Experiment& experiment, const std::string& db_path, const std::string& participant) {
  if (!experiment.straylight_measured) return "";
  std::optional<StoredStraylight> latest;
  int passed_over = 0;
  std::error_code missing;
  if (std::filesystem::exists(db_path, missing)) {
    const ResultStore store(db_path);
    for (const SessionRecord& session : store.load_sessions()) {
      if (session.participant != participant) continue;
      const std::optional<StoredStraylight> measured = stored_straylight(store, session.id);
      if (!measured) continue;
      if (measured->estimate.unreliable || measured->status != "completed") {
        ++passed_over;
        continue;
      }
      if (!latest || measured->session_id > latest->session_id) latest = measured;
    }
  }
  const SourceLocation& where = *experiment.straylight_measured;
  if (!latest)
    throw ConfigError(where, "glare.straylight",
                      "\"measured\": participant '" + participant + "' has no completed, reliable straylight measurement in " +
                          db_path +
                          (passed_over > 0 ? " (" + std::to_string(passed_over) +
                                                 " unfinished or unreliable (a spread above 0.08) passed over)"
                                           : std::string()) +
                          ": run one first ([procedure] type = \"straylight\") with the same --db and --participant, "
                          "or give log10(s) as a number");
  experiment.glare.observer_eye.straylight_log_s = latest->estimate.log_s;
  try {
    check_observer_eye(experiment.glare.observer_eye);
  } catch (const std::invalid_argument& error) {
    throw ConfigError(where, "glare.straylight",
                      "\"measured\" is session " + std::to_string(latest->session_id) + "'s " + error.what());
  }
  char numbers[96];
  std::snprintf(numbers, sizeof numbers, "log(s) %.4f, ESD %.3f", latest->estimate.log_s, latest->estimate.esd_log10);
  return std::string(numbers) + ", " + latest->eye + " eye: session " + std::to_string(latest->session_id) + " of " +
         db_path;
}

}  // namespace glarelab
