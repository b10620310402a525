#pragma once
// The CIE 146:2002 general glare spread function (age- and pigmentation-adjusted Stiles-Holladay
// form): the equivalent veiling luminance per glare illuminance,
//   L_veil / E_glare = 10 / theta^3 + (5 / theta^2 + 0.1 p / theta) (1 + (A / 62.5)^4) + 0.0025 p
// per steradian, theta in degrees (valid 0.1-100 degrees), A the age in years, p the eye's
// pigmentation (0 very dark eyes, 0.5 brown, 1 blue-green). As a PSF it is the scattered light;
// what it does not scatter stays in the image point (the "peak").
//
// Below 0.1 degrees the formula is outside its range and its 10 / theta^3 term has no finite
// integral. The PSF built from it (glare/analytic/analytic_psf.h) holds the value at 0.1 degrees inside that disc
// (a flat core some four display pixels wide at 0.024 degrees per pixel), so the scattered light
// has no hole between the point and 0.1 degrees; the peak is what remains of unit energy.
namespace glarelab {

inline constexpr double kCieGlareMinAngleDeg = 0.1;
inline constexpr double kCieGlareMaxAngleDeg = 100.0;

// The formula itself at any angle > 0 (the `psf --profile-csv` values).
double cie146_glare_spread_per_sr(double angle_deg, double age_years, double pigmentation);
// The age factor 1 + (A / 62.5)^4 the formula multiplies its wide-angle terms by.
double cie146_age_factor(double age_years);
// The formula with its wide-angle terms multiplied by `wide_angle_factor` instead of the age factor:
//   10 / theta^3 + (5 / theta^2 + 0.1 p / theta) F + 0.0025 p.
// An eye whose straylight was measured is this function with the F that gives its s (the way CIE
// 146 itself makes an eye older: docs/STRAYLIGHT.md, glare/analytic/ring_straylight.h).
double cie146_glare_spread_for_factor_per_sr(double angle_deg, double wide_angle_factor, double pigmentation);
// The formula with its core held at 0.1 degrees (what the PSF uses).
double cie146_scattered_per_sr(double angle_deg, double age_years, double pigmentation);

}  // namespace glarelab
