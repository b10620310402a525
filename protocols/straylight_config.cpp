#include "protocols/straylight_config.h"

#include <algorithm>
#include <cmath>
#include <optional>
#include <stdexcept>
#include <string>
#include <utility>

#include "core/number_text.h"
#include "protocols/straylight_model.h"

namespace glarelab {
namespace {

// IEC 61966-2-1:1999: encoded sRGB value in [0, 1] to linear.
double srgb_decode(double encoded) {
  return encoded <= 0.04045 ? encoded / 12.92 : std::pow((encoded + 0.055) / 1.055, 2.4);
}

// SMPTE ST 2084:2014 EOTF: signal N in [0, 1] to cd/m2 (the inverse of the encode pass's PQ).
double pq_signal_to_cd_m2(double signal) {
  constexpr double m1 = 2610.0 / 16384.0, m2 = 2523.0 / 4096.0 * 128.0;
  constexpr double c1 = 3424.0 / 4096.0, c2 = 2413.0 / 4096.0 * 32.0, c3 = 2392.0 / 4096.0 * 32.0;
  const double p = std::pow(std::clamp(signal, 0.0, 1.0), 1.0 / m2);
  return 10000.0 * std::pow(std::max(p - c1, 0.0) / (c2 - c3 * p), 1.0 / m1);
}

// The drive at which the display shows `luminance_cd_m2` (bisection: the luminance rises with
// the drive under every encoding).
double drive_for_luminance(const DisplaySpec& display, double luminance_cd_m2) {
  double low = 0.0, high = 1.0;
  for (int i = 0; i < 60; ++i) {
    const double middle = 0.5 * (low + high);
    (display_luminance_at_drive(display, middle) < luminance_cd_m2 ? low : high) = middle;
  }
  return low;
}

// The framebuffer's next drive level above `drive`.
double next_drive(const DisplaySpec& display, double drive) {
  if (display.bits_per_channel == 16) {
    // Half floats: 10 stored mantissa bits, subnormal spacing 2^-24 below 2^-14.
    return drive + std::max(std::ldexp(std::max(drive, std::ldexp(1.0, -14)), -10), std::ldexp(1.0, -24));
  }
  const double levels = std::ldexp(1.0, display.bits_per_channel == 0 ? 8 : display.bits_per_channel) - 1.0;
  return (std::floor(drive * levels + 1e-9) + 1.0) / levels;
}

std::string encoding_text(const DisplaySpec& display) {
  switch (display.encoding) {
    case DisplayEncoding::srgb: return "srgb";
    case DisplayEncoding::gamma: return "gamma " + number_text(display.gamma);
    case DisplayEncoding::pq: return "pq";
    case DisplayEncoding::table: return "table";
  }
  return "";
}

void check_flicker(TableReader& procedure, const DisplaySpec& display, StraylightSpec& spec) {
  spec.flicker_hz = procedure.number_in_range("flicker_hz", spec.flicker_hz, 4.0, 20.0, "Hz");
  spec.frames_per_cycle = straylight_frames_per_cycle(display.refresh_hz, spec.flicker_hz);
  const double shown_hz = display.refresh_hz / spec.frames_per_cycle;
  if (std::abs(shown_hz - spec.flicker_hz) > kStraylightFlickerTolerance * spec.flicker_hz) {
    procedure.fail("flicker_hz", "a square wave near " + number_text(spec.flicker_hz) + " Hz needs an even, whole number of frames per cycle; at " +
                                     number_text(display.refresh_hz) + " Hz the nearest is " +
                                     std::to_string(spec.frames_per_cycle) + " frames, " + number_text(shown_hz) +
                                     " Hz, more than " + number_text(100.0 * kStraylightFlickerTolerance) +
                                     " % away (60 or 120 Hz give 7.5 Hz, 144 or 240 Hz give 8 Hz)");
  }
}

void check_ring_geometry(TableReader& procedure, const DisplaySpec& display, StraylightSpec& spec) {
  spec.test_field_radius_deg = procedure.number_in_range("test_field_radius_deg", spec.test_field_radius_deg, 0.5, 5.0, "degrees");
  spec.ring_inner_deg = procedure.number_in_range("ring_inner_deg", spec.ring_inner_deg, 1.0, 40.0, "degrees");
  spec.ring_outer_deg = procedure.number_in_range("ring_outer_deg", spec.ring_outer_deg, 1.0, 60.0, "degrees");
  if (!(spec.ring_inner_deg > spec.test_field_radius_deg))
    procedure.fail("ring_inner_deg", "the ring must lie outside the test field: " + number_text(spec.ring_inner_deg) +
                                         " degrees is not beyond test_field_radius_deg = " +
                                         number_text(spec.test_field_radius_deg));
  if (!(spec.ring_outer_deg > spec.ring_inner_deg))
    procedure.fail("ring_outer_deg", "must be larger than ring_inner_deg = " + number_text(spec.ring_inner_deg) +
                                         ", found " + number_text(spec.ring_outer_deg));
  // The ring is centred on the fixation point at the display's centre: its outer edge must be on
  // the screen in every direction (the shorter side limits).
  const double half_extent_deg =
      0.5 * centred_span_deg(display, static_cast<double>(std::min(display.width_px, display.height_px)));
  if (spec.ring_outer_deg > half_extent_deg)
    procedure.fail("ring_outer_deg", "the ring reaches " + number_text(spec.ring_outer_deg) +
                                         " degrees from the centre but the display's shorter side reaches only " +
                                         number_text(half_extent_deg) + " degrees at " +
                                         number_text(display.viewing_distance_mm) + " mm");
}

void check_compensation(TableReader& procedure, const DisplaySpec& display, StraylightSpec& spec) {
  const double k = ring_straylight_constant(spec.ring_inner_deg, spec.ring_outer_deg);
  const double peak = display.peak_luminance_cd_m2;
  const double largest = k * std::pow(10.0, kStraylightMaxCompensationLog10);
  const bool given = procedure.node("ring_luminance_cd_m2") != nullptr;
  spec.ring_luminance_cd_m2 = procedure.number_in_range("ring_luminance_cd_m2", std::min(peak, peak / largest),
                                                        0.1, 10000.0, "cd/m2");
  if (given && spec.ring_luminance_cd_m2 > peak)
    procedure.fail("ring_luminance_cd_m2", "the display's peak is " + number_text(peak) + " cd/m2, found " +
                                               number_text(spec.ring_luminance_cd_m2));
  const double low_cd_m2 = k * std::pow(10.0, kStraylightMinCompensationLog10) * spec.ring_luminance_cd_m2;
  const double high_cd_m2 = largest * spec.ring_luminance_cd_m2;
  const std::string range = "the compensation light (log10 s_c " + number_text(kStraylightMinCompensationLog10) + " to " +
                            number_text(kStraylightMaxCompensationLog10) + ") runs from " + number_text(low_cd_m2) +
                            " to " + number_text(high_cd_m2) + " cd/m2";
  if (high_cd_m2 > peak * (1.0 + 1e-9))
    procedure.fail("ring_luminance_cd_m2", range + ", beyond the display's peak of " + number_text(peak) +
                                               " cd/m2 (at most " + number_text(peak / largest) + " cd/m2 for this ring)");
  const double step_log10 = largest_drive_step_log10(display, low_cd_m2, high_cd_m2);
  if (step_log10 > kStraylightLevelStepLog10)
    procedure.fail("ring_luminance_cd_m2",
                   range + ", where the display's encoding (" + encoding_text(display) + ", " +
                       std::to_string(display.bits_per_channel == 0 ? 8 : display.bits_per_channel) +
                       " bits per channel) steps by up to " + number_text(step_log10) + " log10; the levels need " +
                       number_text(kStraylightLevelStepLog10) +
                       " (a brighter ring, or [display] bits_per_channel = 10)");
  spec.display_glow_cd_m2 = procedure.non_negative_number("display_glow_cd_m2", spec.display_glow_cd_m2);
  // The glow adds glow / (k L_ring) to the straylight the answers measure; once it is as large as
  // the clearest eye's whole straylight the difference left for the eye is noise.
  const double glow_straylight = spec.display_glow_cd_m2 / (k * spec.ring_luminance_cd_m2);
  if (glow_straylight >= std::pow(10.0, kStraylightMinCompensationLog10))
    procedure.fail("display_glow_cd_m2", "the display's stray light is " + number_text(glow_straylight) +
                                             " deg^2/sr in straylight units, as much as a clear eye's (" +
                                             number_text(std::pow(10.0, kStraylightMinCompensationLog10)) +
                                             "): the eye's own could not be told from it");
}

}  // namespace

int straylight_frames_per_cycle(double refresh_hz, double flicker_hz) {
  const double half_cycles = std::round(refresh_hz / flicker_hz / 2.0);
  return 2 * static_cast<int>(std::max(1.0, half_cycles));
}

double display_luminance_at_drive(const DisplaySpec& display, double drive01) {
  const double d = std::clamp(drive01, 0.0, 1.0);
  switch (display.encoding) {
    case DisplayEncoding::srgb: return display.peak_luminance_cd_m2 * srgb_decode(d);
    case DisplayEncoding::gamma: return display.peak_luminance_cd_m2 * std::pow(d, display.gamma);
    case DisplayEncoding::pq: return std::min(pq_signal_to_cd_m2(d), display.peak_luminance_cd_m2);
    case DisplayEncoding::table: {
      double luminance = display.calibration.black_cd_m2();
      for (int channel = 0; channel < 3; ++channel) luminance += display.calibration.channel_gain_cd_m2(channel, d);
      return luminance;
    }
  }
  return 0.0;
}

double largest_drive_step_log10(const DisplaySpec& display, double low_cd_m2, double high_cd_m2) {
  // From the drive level at or below low_cd_m2 up to the first above high_cd_m2: each step's rise
  // relative to the luminance it starts from (or to low_cd_m2, for the step that crosses it).
  double drive = drive_for_luminance(display, low_cd_m2);
  if (display.bits_per_channel != 16) {
    const double levels = std::ldexp(1.0, display.bits_per_channel == 0 ? 8 : display.bits_per_channel) - 1.0;
    drive = std::floor(drive * levels + 1e-9) / levels;
  }
  double largest = 0.0;
  double luminance = display_luminance_at_drive(display, drive);
  while (drive < 1.0 && luminance < high_cd_m2) {
    const double next = std::min(1.0, next_drive(display, drive));
    const double next_luminance = display_luminance_at_drive(display, next);
    if (next_luminance > low_cd_m2) {
      const double base = std::max(luminance, low_cd_m2);
      largest = std::max(largest, std::log10(1.0 + (next_luminance - luminance) / base));
    }
    drive = next;
    luminance = next_luminance;
  }
  return largest;
}

void set_glare_observer_eye(TableReader& top, Experiment& experiment, GlareSpec glare_spec, const ObserverEye& observer_eye) {
  GlareSpec& spec = experiment.glare = std::move(glare_spec);
  const std::optional<double> straylight_log_s = spec.observer_eye.straylight_log_s;
  spec.observer_eye = observer_eye;
  spec.observer_eye.straylight_log_s = straylight_log_s;
  const toml::table* table = top.table("glare");
  if (table == nullptr) return;
  TableReader glare(*table, "glare", top.file());
  if (const toml::node* node = table->get("straylight"); node != nullptr && node->is_string()) {
    if (node->value<std::string>() != "measured")
      glare.fail("straylight", "expected log10(s) as a number, or \"measured\" (the participant's most recent reliable "
                               "straylight measurement in the session's database), found \"" +
                                   *node->value<std::string>() + "\"");
    if (experiment.procedure == "straylight")
      glare.fail("straylight", "\"measured\" takes an earlier measurement; this experiment is the measurement");
    experiment.straylight_measured = glare.value_location("straylight");
    return;
  }
  if (!straylight_log_s) return;
  try {
    check_observer_eye(spec.observer_eye);
  } catch (const std::invalid_argument& error) {
    glare.fail("straylight", error.what());
  }
}

StraylightSpec read_straylight_procedure(TableReader& procedure, const DisplaySpec& display) {
  StraylightSpec spec;
  const std::optional<std::string> eye = procedure.string("eye");
  if (!eye) procedure.fail("eye", "missing required key: the eye tested, \"left\" or \"right\" (the other one covered)");
  if (*eye != "left" && *eye != "right")
    procedure.fail("eye", "must be \"left\" or \"right\", found \"" + *eye + "\"");
  spec.eye = *eye;
  // The range-finding run takes StraylightSchedule's 7 answers; the fixed levels need at least 5
  // more to place a likelihood's peak, and 100 answers is several times the clinic's length.
  spec.answers = static_cast<int>(procedure.integer_in_range("answers", spec.answers, 12, 100));
  spec.cycles = static_cast<int>(procedure.integer_in_range("cycles", spec.cycles, 1, 100));
  check_flicker(procedure, display, spec);
  check_ring_geometry(procedure, display, spec);
  check_compensation(procedure, display, spec);
  return spec;
}

bool read_straylight_design(TableReader& top, Experiment& experiment) {
  const toml::table* table = top.table("procedure");
  const toml::node* type = table != nullptr ? table->get("type") : nullptr;
  if (type == nullptr || type->value<std::string>() != "straylight") return false;
  // The measurement draws its own stimulus and plans its own trials (docs/STRAYLIGHT.md).
  for (const char* section : {"scenes", "conditions", "blocks"})
    if (top.node(section) != nullptr)
      top.fail_at_key(section, std::string("a straylight measurement draws its own stimulus (the ring and the split test "
                                           "field) and plans its own trials: remove [") + section + "]");
  // One eye at a time, the other covered: the stimulus is centred on the one fixation point.
  if (experiment.display.stereo != StereoMode::none)
    throw ConfigError(experiment.stereo_where, "display.stereo",
                      "a straylight measurement tests one eye at a time on the whole display: remove stereo");
  // The test field is dark but for the compensation light, as the model of its flicker assumes.
  if (experiment.display.background_cd_m2 != 0.0)
    TableReader(*top.table("display"), "display", top.file())
        .fail("background_cd_m2", "a straylight measurement needs a dark display around its ring and test field: "
                                  "remove background_cd_m2 (or set it to 0)");
  TableReader procedure(*table, "procedure", top.file());
  procedure.string("type");
  experiment.procedure = "straylight";
  experiment.straylight = read_straylight_procedure(procedure, experiment.display);
  procedure.report_unused();
  return true;
}

toml::table straylight_procedure_toml(const StraylightSpec& spec) {
  return toml::table{{"type", "straylight"},
                     {"eye", spec.eye},
                     {"answers", spec.answers},
                     {"cycles", spec.cycles},
                     {"ring_inner_deg", spec.ring_inner_deg},
                     {"ring_outer_deg", spec.ring_outer_deg},
                     {"ring_luminance_cd_m2", spec.ring_luminance_cd_m2},
                     {"test_field_radius_deg", spec.test_field_radius_deg},
                     {"flicker_hz", spec.flicker_hz},
                     {"display_glow_cd_m2", spec.display_glow_cd_m2}};
}

}  // namespace glarelab
