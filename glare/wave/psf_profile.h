#pragma once
// The radial profile of a glare PSF, as `glarelab psf --profile-csv` writes it: a density per
// steradian at angles from the source, log-spaced from 0.01 to 90 degrees. The analytic models
// give it exactly (AnalyticPsf::profile_per_sr); a PSF image gives it as the azimuthal mean of its
// pixels' densities (pixel value / pixel solid angle) on 1-pixel rings about the centre, read at
// each angle by linear interpolation between rings, up to the angle the image reaches.
#include <string>
#include <vector>

#include "glare/wave/psf.h"

namespace glarelab {

inline constexpr double kProfileFirstAngleDeg = 0.01;
inline constexpr double kProfileLastAngleDeg = 90.0;
inline constexpr int kProfileAnglesPerDecade = 20;

// Log-spaced angles from 0.01 to 90 degrees, both included, at least 20 per decade.
std::vector<double> profile_angles_deg();

// How an image's pixels lie in the visual field. `uniform_angle`: the wave-optics PSF's grid, every
// pixel degrees_per_pixel wide in angle (pixel k from the centre at k degrees_per_pixel, solid angle
// degrees_per_pixel^2 in rad^2). `flat_display`: pixels on a plane whose centre pixel subtends
// degrees_per_pixel (glare/analytic/display_glare_kernel.h's geometry): pixel r from the centre lies at
// atan(r tan(dpp)) and subtends tan^2(dpp) / (1 + r^2 tan^2(dpp))^(3/2) sr.
enum class PixelLayout { uniform_angle, flat_display };

struct ProfilePoint {
  double angle_deg = 0.0;
  double per_sr = 0.0;
};

// The azimuthal-mean profile of `psf` at those `angles_deg` that lie within reach_deg and within
// the image (half its side less one pixel). Three channels are combined with the Rec.709 luminance
// weights (0.2126, 0.7152, 0.0722), which keep a unit-sum PSF at unit sum.
std::vector<ProfilePoint> image_profile_per_sr(const Psf& psf, PixelLayout layout, const std::vector<double>& angles_deg,
                                               double reach_deg);

// The CSV: header `angle_deg,psf_per_sr`, one row per point, 17 significant digits. Throws
// std::runtime_error naming the file when it cannot be written.
void write_profile_csv(const std::string& path, const std::vector<ProfilePoint>& points);

}  // namespace glarelab
