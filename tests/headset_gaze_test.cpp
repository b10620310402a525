// The headset's gaze on each eye's view (runner/display/headset_gaze.h) against hand-checked
// vectors: a rotation about +y by theta turns OpenXR's forward (-z) to the left, so a gaze turned by
// theta meets a view of edges +-45 deg at x = (1 - tan theta) / 2; one turned up by phi (about +x)
// at y = (1 - tan phi) / 2; and a straight gaze on a view whose edges lie at -40 and +50 deg meets it
// at tan 40 / (tan 40 + tan 50) = sin^2 40 deg. Values typed from a calculator, not the code.
#include <gtest/gtest.h>

#include <cmath>

#include "runner/display/headset_gaze.h"

namespace glarelab {
namespace {

constexpr double kPi = 3.14159265358979323846;
const ViewFieldOfView kSquareView{-45.0, 45.0, 45.0, -45.0};
const double kIdentity[4] = {0.0, 0.0, 0.0, 1.0};

// A unit quaternion (x, y, z, w) turning by `deg` about the unit axis (ax, ay, az).
struct Turn {
  double q[4];
  Turn(double ax, double ay, double az, double deg) {
    const double half = deg * kPi / 360.0;
    q[0] = ax * std::sin(half);
    q[1] = ay * std::sin(half);
    q[2] = az * std::sin(half);
    q[3] = std::cos(half);
  }
};

std::optional<ViewGazePoint> point(const double gaze[4], const double view[4], const ViewFieldOfView& fov) {
  return gaze_point_in_view(gaze_direction_in_view(gaze, view), fov);
}

TEST(HeadsetGaze, AStraightGazeMeetsASymmetricViewAtItsCentre) {
  const auto p = point(kIdentity, kIdentity, kSquareView);
  ASSERT_TRUE(p);
  EXPECT_NEAR(p->x, 0.5, 1e-15);
  EXPECT_NEAR(p->y, 0.5, 1e-15);
}

TEST(HeadsetGaze, AGazeTurnedLeftOrUpMeetsTheViewAtItsTangent) {
  const auto left = point(Turn(0, 1, 0, 20.0).q, kIdentity, kSquareView);
  ASSERT_TRUE(left);
  EXPECT_NEAR(left->x, 0.31801488286689883, 1e-12);  // (1 - tan 20 deg) / 2
  EXPECT_NEAR(left->y, 0.5, 1e-12);
  const auto up = point(Turn(1, 0, 0, 15.0).q, kIdentity, kSquareView);
  ASSERT_TRUE(up);
  EXPECT_NEAR(up->x, 0.5, 1e-12);
  EXPECT_NEAR(up->y, 0.36602540378443865, 1e-12);  // (1 - tan 15 deg) / 2 = (1 - (2 - sqrt 3)) / 2
}

TEST(HeadsetGaze, AnAsymmetricViewPlacesAStraightGazeOffItsCentre) {
  const auto p = point(kIdentity, kIdentity, ViewFieldOfView{-40.0, 50.0, 45.0, -45.0});
  ASSERT_TRUE(p);
  EXPECT_NEAR(p->x, 0.41317591116653485, 1e-12);  // sin^2 40 deg
  EXPECT_NEAR(p->y, 0.5, 1e-12);
}

TEST(HeadsetGaze, TheGazeIsTakenInTheViewsOwnFrame) {
  // A view turned 30 deg left: a gaze turned as far is its centre, a straight one lies 30 deg right.
  const Turn view(0, 1, 0, 30.0);
  const auto same = point(Turn(0, 1, 0, 30.0).q, view.q, kSquareView);
  ASSERT_TRUE(same);
  EXPECT_NEAR(same->x, 0.5, 1e-12);
  EXPECT_NEAR(same->y, 0.5, 1e-12);
  const auto straight = point(kIdentity, view.q, kSquareView);
  ASSERT_TRUE(straight);
  EXPECT_NEAR(straight->x, 0.78867513459481287, 1e-12);  // (1 + tan 30 deg) / 2 = (1 + 1 / sqrt 3) / 2
}

TEST(HeadsetGaze, AGazeThatDoesNotPointAheadOfTheViewMeetsNoPoint) {
  EXPECT_FALSE(point(Turn(0, 1, 0, 180.0).q, kIdentity, kSquareView));
  EXPECT_FALSE(point(Turn(0, 1, 0, 100.0).q, kIdentity, kSquareView));
}

}  // namespace
}  // namespace glarelab
