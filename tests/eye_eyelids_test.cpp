// Procedural eyelids and lashes: blink kinematics and occlusion (Ritschel 3.6).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>

#include "glare/eye/eyelids.h"

namespace glarelab {
namespace {

constexpr double kPi = std::numbers::pi;

// Even-odd point-in-polygon test (the contract's rule), written independently of the model.
bool inside(const AperturePolygon& polygon, double x, double y) {
  bool in = false;
  const std::size_t n = polygon.vertices_mm.size() / 2;
  for (std::size_t i = 0, j = n - 1; i < n; j = i++) {
    const double xi = polygon.vertices_mm[2 * i], yi = polygon.vertices_mm[2 * i + 1];
    const double xj = polygon.vertices_mm[2 * j], yj = polygon.vertices_mm[2 * j + 1];
    if ((yi > y) != (yj > y) && x < (xj - xi) * (y - yi) / (yj - yi) + xi) in = !in;
  }
  return in;
}

bool covered(const ApertureGeometry& geometry, double x, double y) {
  for (const AperturePolygon& polygon : geometry.polygons)
    if (inside(polygon, x, y) && polygon.transmittance == 0.0) return true;
  return false;
}

TEST(EyeEyelids, BlinkClosesWithinTheLiteratureDurationAndReopens) {
  EyeParameters p;
  const EyelidModel lids(p, 6);
  // Closing ~100 ms (VanderWerf et al. 2003: the down phase lasts 75-150 ms); opening slower.
  EXPECT_GE(p.blink_closing_duration_s, 0.075);
  EXPECT_LE(p.blink_closing_duration_s, 0.15);
  EXPECT_GT(p.blink_opening_duration_s, p.blink_closing_duration_s);
  for (std::int64_t index = 0; index < 5; ++index) {
    const double onset = lids.blink_onset_s(index);
    EXPECT_GE(onset, static_cast<double>(index) * p.blink_mean_interval_s);
    EXPECT_EQ(lids.blink_closure(onset - 0.01), 0.0);
    EXPECT_NEAR(lids.blink_closure(onset), 0.0, 1e-12);
    EXPECT_NEAR(lids.blink_closure(onset + p.blink_closing_duration_s), 1.0, 1e-12);
    const double end = onset + lids.blink_duration_s();
    EXPECT_NEAR(lids.blink_closure(end), 0.0, 1e-12);
    EXPECT_EQ(lids.blink_closure(end + 0.01), 0.0);
    double previous = 0.0;
    for (double t = onset; t <= onset + p.blink_closing_duration_s; t += 0.001) {
      EXPECT_GE(lids.blink_closure(t), previous - 1e-12);
      previous = lids.blink_closure(t);
    }
    previous = 1.0;
    for (double t = onset + p.blink_closing_duration_s + p.blink_closed_duration_s + 0.001; t <= end; t += 0.001) {
      EXPECT_LE(lids.blink_closure(t), previous + 1e-12);
      previous = lids.blink_closure(t);
    }
  }
  // Rate: 17 blinks per minute at rest (Bentivoglio et al. 1997).
  int blinks = 0;
  bool closed = false;
  for (double t = 0.0; t < 600.0; t += 0.01) {
    const bool now = lids.blink_closure(t) > 0.5;
    if (now && !closed) ++blinks;
    closed = now;
  }
  EXPECT_NEAR(blinks / 10.0, 17.0, 1.0);
}

TEST(EyeEyelids, ClosedLidsCoverTheLargestPupilAndOpenLidsClearTheCentre) {
  EyeParameters p;
  const EyelidModel lids(p, 6);
  ApertureGeometry closed, open;
  lids.append_occluders(1.0, closed);
  lids.append_occluders(0.0, open);
  ASSERT_EQ(closed.polygons.size(), 2u);
  for (double x = -4.5; x <= 4.5; x += 0.05)
    for (double y = -4.5; y <= 4.5; y += 0.05) {
      if (x * x + y * y > 4.5 * 4.5) continue;
      ASSERT_TRUE(covered(closed, x, y)) << "gap in the closed lids at (" << x << ", " << y << ") mm";
    }
  // Open lids leave a 7 mm pupil clear (upper margin at +4.5 mm, lower at -5.5 mm).
  for (double x = -3.5; x <= 3.5; x += 0.05)
    for (double y = -3.5; y <= 3.5; y += 0.05)
      if (x * x + y * y <= 3.5 * 3.5) {
        ASSERT_FALSE(covered(open, x, y)) << x << ", " << y;
      }
  // Lashes hang from the margins into the opening and move with them.
  ASSERT_EQ(open.lines.size(), static_cast<std::size_t>(p.upper_eyelash_count + p.lower_eyelash_count));
  const ApertureLine& upper_open = open.lines.front();
  const ApertureLine& upper_closed = closed.lines.front();
  EXPECT_LT(upper_open.y1_mm, upper_open.y0_mm);
  EXPECT_LT(upper_closed.y0_mm, upper_open.y0_mm);
}

TEST(EyeEyelids, RecordedBlinksReplaceTheScheduleWithTheSameProfile) {
  const EyeParameters p;
  EyelidModel lids(p, 3);
  const double scheduled_s = lids.blink_onset_s(0) + p.blink_closing_duration_s;  // closed by the schedule
  EXPECT_EQ(lids.blink_closure(scheduled_s), 1.0);
  // A detected blink 10.0-10.4 s: half-cosine closing over 0.1 s, closed until the offset, half-cosine
  // opening over 0.2 s from it.
  lids.set_recorded_blinks({{10.0, 10.4}});
  EXPECT_EQ(lids.blink_closure(scheduled_s), 0.0) << "the schedule is off";
  EXPECT_EQ(lids.blink_closure(9.99), 0.0);
  EXPECT_NEAR(lids.blink_closure(10.05), 0.5, 1e-12);                          // (1 - cos(pi / 2)) / 2
  EXPECT_NEAR(lids.blink_closure(10.025), 0.5 * (1.0 - std::cos(0.25 * kPi)), 1e-12);
  EXPECT_EQ(lids.blink_closure(10.2), 1.0);
  EXPECT_EQ(lids.blink_closure(10.4), 1.0);
  EXPECT_NEAR(lids.blink_closure(10.5), 0.5, 1e-12);
  EXPECT_NEAR(lids.blink_closure(10.6), 0.0, 1e-12);
  // A blink shorter than the closing phase still closes the lids fully before they open.
  lids.set_recorded_blinks({{10.0, 10.4}, {20.0, 20.02}});
  EXPECT_EQ(lids.blink_closure(20.1), 1.0);
  EXPECT_NEAR(lids.blink_closure(20.2), 0.5, 1e-12);
  // Still open (no offset yet): closed for as long as it lasts.
  lids.set_recorded_blinks({{10.0, 10.4}, {20.0, INFINITY}});
  EXPECT_EQ(lids.blink_closure(35.0), 1.0);
  // A new blink while the last one is still opening: the larger closure, no jump open.
  lids.set_recorded_blinks({{30.0, 30.1}, {30.15, 30.3}});
  EXPECT_NEAR(lids.blink_closure(30.16), std::max(1.0 - 0.5 * (1.0 - std::cos(kPi * 0.3)),
                                                  0.5 * (1.0 - std::cos(kPi * 0.1))), 1e-12);
  // Bad input names the model.
  EXPECT_THROW(lids.set_recorded_blinks({{2.0, 1.0}}), std::invalid_argument);
  EXPECT_THROW(lids.set_recorded_blinks({{2.0, 3.0}, {1.0, 1.5}}), std::invalid_argument);
}

TEST(EyeEyelids, SquintNarrowsTheOpeningConstantly) {
  EyeParameters p;
  p.squint_closure = 0.4;
  const EyelidModel lids(p, 6);
  const double between_blinks = lids.blink_onset_s(2) - 0.2;
  EXPECT_NEAR(lids.lid_closure(between_blinks), 0.4, 1e-15);
  EXPECT_NEAR(lids.lid_closure(lids.blink_onset_s(2) + p.blink_closing_duration_s), 1.0, 1e-12);
  ApertureGeometry squinting;
  lids.append_occluders(0.4, squinting);
  EXPECT_TRUE(covered(squinting, 0.0, 2.0));  // the upper lid has come down over the top of the pupil
  EXPECT_FALSE(covered(squinting, 0.0, 0.0));
}

}  // namespace
}  // namespace glarelab
