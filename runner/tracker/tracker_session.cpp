#include "runner/tracker/tracker_session.h"

#include <cmath>
#include <limits>
#include <sstream>
#include <utility>

#include "core/errors.h"
#include "core/clock.h"
#include "core/number_text.h"

namespace glarelab {

TrackerSession::TrackerSession(const TrackerOptions& options, std::uint64_t seed) : options_(options) {
  // A bad --tracker value or replay file is bad input (exit 2); only an absent device is exit 3.
  try {
    source_ = make_tracker_source(options.spec, seed);
  } catch (const TrackerError& error) {
    throw ConfigError({"--tracker", 0, 0}, "tracker", error.what());
  }
  if (options_.pupil_model != "measured" && options_.pupil_model != "calibrated")
    throw ConfigError({"--pupil-model", 0, 0}, "pupil-model", "'" + options_.pupil_model + "': choose measured or calibrated");
  if (!(options_.calibration_screen_s > 0.0))
    throw ConfigError({"--pupil-calibration-s", 0, 0}, "pupil-calibration-s", "must be positive");
}

TrackerSession::~TrackerSession() {
  if (source_) source_->stop();
}

void TrackerSession::adopt_display_tracker(std::unique_ptr<TrackerSource> source) {
  if (!source_) source_ = std::move(source);
}

std::optional<std::string> TrackerSession::start(const SessionClock& clock) {
  if (!source_) return std::nullopt;
  try {
    source_->start(clock);
  } catch (const TrackerError& error) {
    if (!options_.optional) throw;
    source_.reset();
    return std::string(error.what()) + "; continuing without a tracker (--tracker-optional)";
  }
  return std::nullopt;
}

void TrackerSession::attach_log(const std::string& db_path, std::int64_t session_id) {
  if (source_) logger_ = std::make_unique<TrackerLogger>(db_path, session_id);
}

void TrackerSession::on_frame(double now_s) {
  if (!source_) return;
  polled_ = true;
  TrackerBatch batch = source_->poll(now_s);
  if (batch.empty()) return;
  samples_ += static_cast<std::int64_t>(batch.samples.size());
  std::vector<FilteredPupil> filtered;
  const std::size_t timed_out_before = filter_.timed_out_blinks();
  filter_.add_batch(batch, &filtered);
  if (filter_.timed_out_blinks() > timed_out_before)
    batch.notices.push_back({now_s, "tracker_blink_timeout",
                             "a blink onset had no offset within " + number_text(filter_.settings().max_blink_s) +
                                 " s; the blink was ended there (" + std::to_string(filter_.timed_out_blinks()) +
                                 " so far)"});
  std::vector<FilteredPupil>* keep = phase_ == Phase::black ? &black_phase_ : phase_ == Phase::white ? &white_phase_ : nullptr;
  if (keep != nullptr) keep->insert(keep->end(), filtered.begin(), filtered.end());
  track_gaze_and_blinks(batch, filtered);
  if (logger_) logger_->enqueue(std::move(batch));
}

// add_batch gives one FilteredPupil per sample, in order.
void TrackerSession::track_gaze_and_blinks(const TrackerBatch& batch, const std::vector<FilteredPupil>& filtered) {
  const double min_confidence = filter_.settings().min_confidence;
  for (std::size_t k = 0; k < batch.samples.size() && k < filtered.size(); ++k) {
    const TrackerSample& sample = batch.samples[k];
    if (sample.valid && sample.confidence >= min_confidence && sample.has_gaze()) {
      latest_gaze_ = TrackerGaze{sample.session_time_s, sample.gaze_x, sample.gaze_y};
      gaze_track_.add({sample.session_time_s, sample.gaze_x, sample.gaze_y});
      eye_gaze_[eye_index(sample.eye)] = latest_gaze_;
      eye_gaze_track_[eye_index(sample.eye)].add({sample.session_time_s, sample.gaze_x, sample.gaze_y});
    }
    const int eye = filtered[k].eye;
    eye_seen_[eye] = true;
    eye_in_blink_[eye] = filtered[k].blink;
    std::vector<TrackerBlinkInterval>& own = eye_blinks_[eye_index(eye)];
    const bool own_open = !own.empty() && std::isinf(own.back().offset_s);
    if (!own_open && filtered[k].blink)
      own.push_back({sample.session_time_s, std::numeric_limits<double>::infinity()});
    else if (own_open && !filtered[k].blink)
      own.back().offset_s = sample.session_time_s;
    const bool open_blink = !blinks_.empty() && std::isinf(blinks_.back().offset_s);
    const bool all_in_blink = (!eye_seen_[0] || eye_in_blink_[0]) && (!eye_seen_[1] || eye_in_blink_[1]);
    if (!open_blink && all_in_blink)
      blinks_.push_back({sample.session_time_s, std::numeric_limits<double>::infinity()});
    else if (open_blink && !filtered[k].blink)
      blinks_.back().offset_s = sample.session_time_s;
  }
}

void TrackerSession::begin_calibration_phase(bool black_screen) { phase_ = black_screen ? Phase::black : Phase::white; }

std::string TrackerSession::finish_calibration(double now_s) {
  phase_ = Phase::none;
  std::string why;
  range_ = calibrate_pupil_range(black_phase_, white_phase_, &why);
  const std::string line = range_ ? "pupil range " + range_->describe() + "; model pupil mapped onto 2-8 mm"
                                  : "pupil calibration failed: " + why + "; the model pupil is the measured diameter";
  if (logger_) {
    TrackerBatch note;
    note.notices.push_back({now_s, "pupil_calibration", line});
    logger_->enqueue(std::move(note));
  }
  black_phase_.clear();
  white_phase_.clear();
  return line;
}

double TrackerSession::model_pupil_mm() const {
  const double measured = filter_.model_pupil_mm();
  return range_ ? map_pupil_to_model_range(measured, *range_) : measured;
}

std::optional<double> TrackerSession::measured_eye_pupil_mm(int eye) const {
  if (!source_) return std::nullopt;
  const std::optional<double> measured = filter_.eye_pupil_mm(eye);
  if (!measured) return std::nullopt;
  return range_ ? map_pupil_to_model_range(*measured, *range_) : *measured;
}

std::optional<double> TrackerSession::measured_pupil_mm() const {
  if (!source_ || !filter_.has_measurement()) return std::nullopt;
  return model_pupil_mm();
}

std::string TrackerSession::finish(double now_s) {
  if (!source_ || finished_) return {};
  finished_ = true;
  source_->stop();
  on_frame(now_s);  // what arrived between the last frame and stop()
  const TrackerStatus status = source_->status();
  std::ostringstream line;
  line.precision(3);
  line << "tracker " << source_->description() << ": " << samples_ << " samples, ";
  if (filter_.gaze_only() > 0) line << filter_.gaze_only() << " with gaze alone (no pupil), ";
  line << filter_.rejected() << " rejected by the pupil filter, " << status.malformed_messages
       << " malformed messages skipped";
  if (source_->live())
    line << ", " << status.connection_losses << " connection losses, " << status.reconnections
         << " reconnections (longest gap " << status.longest_gap_s << " s), " << status.clock_faults
         << " clock replies that were not a time";
  if (logger_) {
    TrackerBatch note;
    note.notices.push_back({now_s, "tracker_summary", line.str()});
    logger_->enqueue(std::move(note));
    logger_->finish();
  }
  return line.str();
}

}  // namespace glarelab
