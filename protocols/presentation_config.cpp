// [presentation]: screens, fixation, inter-stimulus interval, response window, feedback and text.
// Read through TableReader, so a misspelt key stops the run (protocols/toml_table_reader.h).
#include "protocols/presentation_config.h"

#include <algorithm>
#include <limits>

#include "core/display_spec.h"
#include "core/number_text.h"
#include "protocols/experiment.h"
#include "protocols/stimulus_duration.h"
#include "protocols/toml_table_reader.h"

namespace glarelab {
namespace {

std::string read_text(TableReader& reader, std::string_view key, const std::string& fallback, bool may_be_empty) {
  const std::optional<std::string> value = reader.string(key);
  if (!value) return fallback;
  if (!may_be_empty && value->empty()) reader.fail(key, "must not be empty");
  return *value;
}

void insert_duration(toml::table& table, const char* frames_key, const char* seconds_key, const FrameCount& count) {
  if (count.seconds) {
    table.insert(seconds_key, *count.seconds);
  } else {
    table.insert(frames_key, count.frames);
  }
}

}  // namespace

PresentationSpec read_presentation_section(TableReader& top, const Experiment& experiment) {
  PresentationSpec spec;
  // Without a [presentation] table the defaults still meet the checks below (text that fits the
  // display, no brighter than its white): the stored configuration writes them out, and it must
  // read back (the experiment_file fuzz target found a display too small for the default text).
  static const toml::table kNoTable;
  const toml::table* table = top.table("presentation");
  TableReader reader(table != nullptr ? *table : kNoTable, "presentation", top.file());
  const double refresh_hz = experiment.display.refresh_hz;

  spec.instructions = read_text(reader, "instructions", spec.instructions, true);
  if (const std::optional<std::int64_t> every = reader.integer("break_every_trials")) {
    if (*every < 0 || *every > std::numeric_limits<int>::max())
      reader.fail("break_every_trials", "must be >= 0 (0: no breaks), found " + number_text(*every));
    spec.break_every_trials = static_cast<int>(*every);
  }
  spec.break_text = read_text(reader, "break_text", spec.break_text, false);
  spec.screen_min = read_frame_count(reader, "screen_min_frames", "screen_min_duration_s", refresh_hz, spec.screen_min, true);

  spec.fixation = read_frame_count(reader, "fixation_frames", "fixation_duration_s", refresh_hz, spec.fixation, true);
  spec.fixation_size_deg = reader.positive_number("fixation_size_deg", spec.fixation_size_deg);
  spec.inter_stimulus = read_frame_count(reader, "isi_frames", "isi_duration_s", refresh_hz, spec.inter_stimulus, true);

  if (const std::optional<double> window = reader.number("response_window_s")) {
    if (*window < 0.0) reader.fail("response_window_s", "must be >= 0 (0: unlimited), found " + number_text(*window));
    // The adjustment task ends when the observer accepts the match; a deadline would cut it short.
    if (*window > 0.0 && experiment.procedure == "adjustment")
      reader.fail("response_window_s", "the adjustment task has no response window (it ends when the observer accepts)");
    // In a sequential trial answers count from the second interval's onset, so a window that
    // closes before it could never be met.
    const ForcedChoiceSpec& choice = experiment.forced_choice;
    const double second_onset_s = (choice.stimulus_frames + spec.inter_stimulus.frames) / refresh_hz;
    if (*window > 0.0 && choice.layout == "sequential" && *window <= second_onset_s)
      reader.fail("response_window_s", "must be longer than the first interval and the inter-stimulus interval (" +
                                           number_text(second_onset_s) + " s): answers count from the second "
                                           "interval's onset");
    spec.response_window_s = *window;
  }

  if (const std::optional<std::string> feedback = reader.string("feedback")) {
    if (*feedback == "none") {
      spec.feedback = FeedbackKind::none;
    } else if (*feedback == "text") {
      spec.feedback = FeedbackKind::text;
    } else {
      reader.fail("feedback", "unsupported feedback '" + *feedback + "' (supported: 'none', 'text')");
    }
  }
  spec.feedback_duration =
      read_frame_count(reader, "feedback_frames", "feedback_duration_s", refresh_hz, spec.feedback_duration, false);
  spec.feedback_correct_text = read_text(reader, "feedback_correct_text", spec.feedback_correct_text, false);
  spec.feedback_wrong_text = read_text(reader, "feedback_wrong_text", spec.feedback_wrong_text, false);
  spec.feedback_timeout_text = read_text(reader, "feedback_timeout_text", spec.feedback_timeout_text, false);

  spec.text_height_deg = reader.positive_number("text_height_deg", spec.text_height_deg);
  // One line of text must fit on the display: taller text cannot be rasterised onto it.
  const double display_height_deg = centred_span_deg(experiment.display, experiment.display.height_px);
  if (spec.text_height_deg > display_height_deg)
    reader.fail("text_height_deg", "must fit the display: at most " + number_text(display_height_deg) +
                                       " deg (its height at viewing_distance_mm), found " +
                                       number_text(spec.text_height_deg) +
                                       (table != nullptr && table->contains("text_height_deg") ? "" : " (the default; set it in [presentation])"));
  spec.text_cd_m2 = reader.positive_number("text_cd_m2", spec.text_cd_m2);
  // The default text luminance on a display dimmer than it: the display's white.
  if (!(table != nullptr && table->contains("text_cd_m2")))
    spec.text_cd_m2 = std::min(spec.text_cd_m2, experiment.display.peak_luminance_cd_m2);
  // Text is drawn on the display, not through the simulated eye: brighter than white would clip.
  if (spec.text_cd_m2 > experiment.display.peak_luminance_cd_m2)
    reader.fail("text_cd_m2", "must not exceed the display's peak_luminance_cd_m2 (" +
                                  number_text(experiment.display.peak_luminance_cd_m2) + "), found " +
                                  number_text(spec.text_cd_m2));
  spec.question_above_stimuli = reader.boolean("question_above_stimuli").value_or(spec.question_above_stimuli);
  reader.report_unused();
  return spec;
}

toml::table presentation_section_toml(const PresentationSpec& spec) {
  toml::table table{{"instructions", spec.instructions},
                    {"break_every_trials", spec.break_every_trials},
                    {"break_text", spec.break_text}};
  insert_duration(table, "screen_min_frames", "screen_min_duration_s", spec.screen_min);
  insert_duration(table, "fixation_frames", "fixation_duration_s", spec.fixation);
  table.insert("fixation_size_deg", spec.fixation_size_deg);
  insert_duration(table, "isi_frames", "isi_duration_s", spec.inter_stimulus);
  table.insert("response_window_s", spec.response_window_s);
  table.insert("feedback", spec.feedback == FeedbackKind::text ? "text" : "none");
  insert_duration(table, "feedback_frames", "feedback_duration_s", spec.feedback_duration);
  table.insert("feedback_correct_text", spec.feedback_correct_text);
  table.insert("feedback_wrong_text", spec.feedback_wrong_text);
  table.insert("feedback_timeout_text", spec.feedback_timeout_text);
  table.insert("text_height_deg", spec.text_height_deg);
  table.insert("text_cd_m2", spec.text_cd_m2);
  table.insert("question_above_stimuli", spec.question_above_stimuli);
  return table;
}

std::vector<std::string> describe_presentation_roundings(const PresentationSpec& spec, double refresh_hz) {
  std::vector<std::string> roundings;
  const std::pair<const char*, const FrameCount*> durations[] = {{"screen_min_duration_s", &spec.screen_min},
                                                                 {"fixation_duration_s", &spec.fixation},
                                                                 {"isi_duration_s", &spec.inter_stimulus},
                                                                 {"feedback_duration_s", &spec.feedback_duration}};
  for (const auto& [key, count] : durations) {
    const std::string text = describe_rounding(key, *count, refresh_hz);
    if (!text.empty()) roundings.push_back("presentation." + text);
  }
  return roundings;
}

}  // namespace glarelab
