// [procedure] type = "straylight": its keys read strictly, and the displays that cannot show the
// measurement refused at load with the key's file:line:column (docs/STRAYLIGHT.md).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>

#include <toml++/toml.h>

#include "protocols/straylight_config.h"

namespace glarelab {
namespace {

// A 27" 4K panel at 60 cm: 3840 x 2160 px of 0.155 mm reach 15.8 degrees up and down; 10 bits.
DisplaySpec lab_display() {
  DisplaySpec display;
  display.width_px = 3840;
  display.height_px = 2160;
  display.pixel_pitch_mm = 0.155;
  display.viewing_distance_mm = 600.0;
  display.refresh_hz = 60.0;
  display.peak_luminance_cd_m2 = 250.0;
  display.encoding = DisplayEncoding::gamma;
  display.gamma = 2.2;
  display.bits_per_channel = 10;
  return display;
}

// The [procedure] table starts on line 1, its first key on line 2.
StraylightSpec read(const std::string& keys, const DisplaySpec& display) {
  const toml::table root = toml::parse("[procedure]\n" + keys, std::string_view("s.toml"));
  TableReader reader(*root["procedure"].as_table(), "procedure", "s.toml");
  reader.string("type");
  StraylightSpec spec = read_straylight_procedure(reader, display);
  reader.report_unused();
  return spec;
}

std::string refusal(const std::string& keys, const DisplaySpec& display) {
  try {
    read(keys, display);
  } catch (const ConfigError& error) {
    return error.what();
  }
  return "no error";
}

double ring_k(double inner_deg, double outer_deg) {
  const double rad = std::numbers::pi / 180.0;
  return 2.0 * std::numbers::pi * rad * rad * std::log(outer_deg / inner_deg);
}

TEST(StraylightConfig, DefaultsAreTheClinicalRingAt7point5HzOnA60HzDisplay) {
  const StraylightSpec spec = read("type = \"straylight\"\neye = \"right\"\n", lab_display());
  EXPECT_EQ(spec.eye, "right");
  EXPECT_EQ(spec.answers, 25);
  EXPECT_EQ(spec.ring_inner_deg, 5.0);
  EXPECT_EQ(spec.ring_outer_deg, 10.0);
  EXPECT_EQ(spec.test_field_radius_deg, 2.0);
  // 60 / 8 = 7.5 frames per cycle: the even whole number nearest is 8, 7.5 Hz.
  EXPECT_EQ(spec.frames_per_cycle, 8);
  // k 10^2.8 = 1.327e-3 x 631 = 0.837 < 1: the display's peak can compensate a ring at its peak.
  EXPECT_NEAR(ring_k(5.0, 10.0) * std::pow(10.0, 2.8), 0.8371, 1e-4);
  EXPECT_EQ(spec.ring_luminance_cd_m2, 250.0);
  EXPECT_EQ(spec.display_glow_cd_m2, 0.0);
}

TEST(StraylightConfig, KeysAreTakenAndAWiderRingDefaultsToWhatThePeakCanCompensate) {
  const StraylightSpec spec =
      read("type = \"straylight\"\neye = \"left\"\nanswers = 30\nring_inner_deg = 4\nring_outer_deg = 12\n"
           "test_field_radius_deg = 1.5\nflicker_hz = 8\ndisplay_glow_cd_m2 = 0.05\n",
           lab_display());
  EXPECT_EQ(spec.eye, "left");
  EXPECT_EQ(spec.answers, 30);
  EXPECT_EQ(spec.test_field_radius_deg, 1.5);
  EXPECT_EQ(spec.display_glow_cd_m2, 0.05);
  // k(4, 12) 10^2.8 = 1.22 > 1: the ring is dimmed until its largest compensation is the peak.
  EXPECT_NEAR(spec.ring_luminance_cd_m2, 250.0 / (ring_k(4.0, 12.0) * std::pow(10.0, 2.8)), 1e-9);
  EXPECT_LT(spec.ring_luminance_cd_m2, 250.0);
}

TEST(StraylightConfig, FramesPerCycleAreEvenAndNearTheAskedFrequency) {
  // The table: 7.5 Hz at 60 or 120 Hz, 8 Hz at 144 or 240 Hz.
  EXPECT_EQ(straylight_frames_per_cycle(60.0, 8.0), 8);
  EXPECT_EQ(straylight_frames_per_cycle(120.0, 8.0), 16);
  EXPECT_EQ(straylight_frames_per_cycle(144.0, 8.0), 18);
  EXPECT_EQ(straylight_frames_per_cycle(240.0, 8.0), 30);
  EXPECT_EQ(straylight_frames_per_cycle(50.0, 8.0), 6);  // 8.33 Hz
  for (const double hz : {60.0, 75.0, 85.0, 100.0, 120.0, 144.0, 165.0, 240.0}) {
    DisplaySpec display = lab_display();
    display.refresh_hz = hz;
    const StraylightSpec spec = read("eye = \"right\"\n", display);
    EXPECT_EQ(spec.frames_per_cycle % 2, 0) << hz;
    EXPECT_NEAR(hz / spec.frames_per_cycle, 8.0, 0.8) << hz;
  }
}

TEST(StraylightConfig, ARefreshRateWithNoEvenCycleNear8HzIsRefusedAtFlickerHz) {
  DisplaySpec display = lab_display();
  display.refresh_hz = 24.0;  // 3 frames per cycle: 2 give 12 Hz, 4 give 6 Hz
  const std::string message = refusal("eye = \"right\"\nflicker_hz = 8\n", display);
  EXPECT_NE(message.find("s.toml:3:14"), std::string::npos) << message;
  EXPECT_NE(message.find("procedure.flicker_hz"), std::string::npos) << message;
  EXPECT_NE(message.find("even, whole number of frames"), std::string::npos) << message;
  // Without the key the refusal is at the table, still naming it.
  const std::string absent = refusal("eye = \"right\"\n", display);
  EXPECT_NE(absent.find("s.toml:1:1"), std::string::npos) << absent;
  EXPECT_NE(absent.find("procedure.flicker_hz"), std::string::npos) << absent;
}

TEST(StraylightConfig, AnEncodingThatCannotResolveTheLevelsIsRefused) {
  DisplaySpec display = lab_display();
  display.bits_per_channel = 8;
  const std::string message = refusal("eye = \"right\"\nring_luminance_cd_m2 = 250\n", display);
  EXPECT_NE(message.find("s.toml:3:24"), std::string::npos) << message;
  EXPECT_NE(message.find("procedure.ring_luminance_cd_m2"), std::string::npos) << message;
  EXPECT_NE(message.find("bits_per_channel"), std::string::npos) << message;
  // The closed form for a gamma encoding, L(v) = peak (v / N)^gamma: the relative step
  // (L(v + 1) - L(v)) / L(v) falls as v rises, so the coarsest is the step across the lowest
  // compensation (code v0 = floor(N (L / peak)^(1 / gamma)) to v0 + 1, relative to it) or the next.
  const double low = ring_k(5.0, 10.0) * std::pow(10.0, 0.6) * 250.0, high = ring_k(5.0, 10.0) * std::pow(10.0, 2.8) * 250.0;
  for (const int bits : {8, 10}) {
    display.bits_per_channel = bits;
    const double n = std::ldexp(1.0, bits) - 1.0;
    const auto luminance = [&](double v) { return 250.0 * std::pow(v / n, 2.2); };
    const double v0 = std::floor(n * std::pow(low / 250.0, 1.0 / 2.2));
    const double across = std::log10(1.0 + (luminance(v0 + 1.0) - luminance(v0)) / low);
    const double next = std::log10(luminance(v0 + 2.0) / luminance(v0 + 1.0));
    EXPECT_NEAR(largest_drive_step_log10(display, low, high), std::max(across, next), 1e-9) << bits;
  }
  // 8 bits step by about 0.04 there, 10 bits by about 0.01.
  display.bits_per_channel = 8;
  EXPECT_GT(largest_drive_step_log10(display, low, high), 0.03);
  display.bits_per_channel = 10;
  EXPECT_LT(largest_drive_step_log10(display, low, high), 0.012);
  // Half floats resolve any level: relative steps of 2^-10 in the drive.
  display.bits_per_channel = 16;
  EXPECT_LT(largest_drive_step_log10(display, low, high), 2.2 * std::log10(1.0 + std::ldexp(1.0, -10)) * 1.01);
}

TEST(StraylightConfig, DriveToLuminanceInvertsEachEncoding) {
  DisplaySpec display = lab_display();
  display.encoding = DisplayEncoding::srgb;
  // IEC 61966-2-1: 0.5 encoded is 0.2140 linear.
  EXPECT_NEAR(display_luminance_at_drive(display, 0.5), 250.0 * 0.21404, 250.0 * 1e-4);
  EXPECT_DOUBLE_EQ(display_luminance_at_drive(display, 1.0), 250.0);
  display.encoding = DisplayEncoding::pq;
  display.peak_luminance_cd_m2 = 1000.0;
  // ST 2084: signal 0.5 is 92.2 cd/m2, 0.75 is 983 cd/m2.
  EXPECT_NEAR(display_luminance_at_drive(display, 0.5), 92.25, 0.05);
  EXPECT_NEAR(display_luminance_at_drive(display, 0.75), 983.0, 1.0);
}

TEST(StraylightConfig, ARingBeyondTheDisplayIsRefusedAtRingOuterDeg) {
  DisplaySpec display = lab_display();
  display.width_px = 1280;
  display.height_px = 720;
  display.pixel_pitch_mm = 0.25;  // 90 mm up from the centre at 600 mm: 8.5 degrees
  const std::string message = refusal("eye = \"right\"\nring_outer_deg = 10\n", display);
  EXPECT_NE(message.find("s.toml:3:18"), std::string::npos) << message;
  EXPECT_NE(message.find("procedure.ring_outer_deg"), std::string::npos) << message;
  EXPECT_NE(message.find("8.53"), std::string::npos) << message;
  EXPECT_EQ(read("eye = \"right\"\nring_inner_deg = 4\nring_outer_deg = 8\n", display).ring_outer_deg, 8.0);
}

// Each refusal names the file, the line and column of the offending value (the table's own place
// when a required key is absent) and the key.
void expect_refused_at(const std::string& keys, const std::string& place, const std::string& key,
                       const std::string& reason, const DisplaySpec& display) {
  const std::string message = refusal(keys, display);
  EXPECT_NE(message.find("s.toml:" + place + ":"), std::string::npos) << message;
  EXPECT_NE(message.find(key), std::string::npos) << message;
  EXPECT_NE(message.find(reason), std::string::npos) << message;
}

TEST(StraylightConfig, BadValuesAreRefusedAtTheirKey) {
  const DisplaySpec display = lab_display();
  expect_refused_at("", "1:1", "procedure.eye", "eye", display);
  expect_refused_at("eye = \"both\"\n", "2:7", "procedure.eye", "both", display);
  expect_refused_at("eye = \"right\"\nanswers = 5\n", "3:11", "procedure.answers", "12", display);
  expect_refused_at("eye = \"right\"\nring_inner_deg = 1.5\n", "3:18", "procedure.ring_inner_deg",
                    "outside the test field", display);
  expect_refused_at("eye = \"right\"\nring_inner_deg = 8\nring_outer_deg = 6\n", "4:18", "procedure.ring_outer_deg",
                    "ring_inner_deg", display);
  expect_refused_at("eye = \"right\"\nring_luminance_cd_m2 = 300\n", "3:24", "procedure.ring_luminance_cd_m2",
                    "peak is 250", display);
  expect_refused_at("eye = \"right\"\nring_luminance_cd_m2 = -1\n", "3:24", "procedure.ring_luminance_cd_m2", "", display);
  expect_refused_at("eye = \"right\"\ntest_field_radius_deg = 0.2\n", "3:25", "procedure.test_field_radius_deg", "",
                    display);
  expect_refused_at("eye = \"right\"\nflicker_hz = 30\n", "3:14", "procedure.flicker_hz", "", display);
  // A 3-15 degree ring needs k 10^2.8 = 1.93 times its luminance at the largest compensation.
  expect_refused_at("eye = \"right\"\nring_inner_deg = 3\nring_outer_deg = 15\nring_luminance_cd_m2 = 250\n", "5:24",
                    "procedure.ring_luminance_cd_m2", "beyond the display's peak", display);
  // 1 cd/m2 of glow around a 250 cd/m2 ring is 3.0 deg^2/sr; 2 cd/m2 is 6.0, more than a clear eye's 4.
  EXPECT_EQ(read("eye = \"right\"\ndisplay_glow_cd_m2 = 1\n", display).display_glow_cd_m2, 1.0);
  expect_refused_at("eye = \"right\"\ndisplay_glow_cd_m2 = 2\n", "3:22", "procedure.display_glow_cd_m2", "", display);
  expect_refused_at("eye = \"right\"\ndisplay_glow_cd_m2 = -0.1\n", "3:22", "procedure.display_glow_cd_m2", "", display);
  expect_refused_at("eye = \"right\"\nring_radius = 2\n", "3", "procedure.ring_radius", "", display);
}

}  // namespace
}  // namespace glarelab
