#pragma once
// Loss of visual acuity in the dark (Luidolt 2020, section 5.3, after Krawczyk et al. 2005): the
// frame is converted to CIE L*a*b* (lab_colour.h, reference white Y_n = 100 cd/m2), L* is blurred
// with a Gaussian whose width depends on each pixel's lightness, a* and b* are kept, and the result
// is converted back to linear Rec.709 in cd/m2.
//
// Resolvable frequency (Eq. 5.14, Larson, Rushmeier and Piatko 1997), cycles per degree:
//   R(Y) = 17.25 atan(1.4 log10 Y + 0.35) + 25.72;   R(100) = 47.5, R(0.01) = 5.3.
// Blur width (Eq. 5.15, Krawczyk et al.), written in pixels with the display's pixels per degree
// (ppd = width / fov in the thesis; here from viewing_distance_mm and pixel_pitch_mm at the screen
// centre, stimuli/display_model.h):
//   sigma_px(L*) = ppd / (1.86 sqrt(2) R(LtoY(L*))).
// The printed equation is a fraction whose denominator we read as fov 1.86 sqrt(2) R. This reading
// is the one where R is what its name says: a Gaussian of that sigma passes a grating of frequency
// f with contrast exp(-2 pi^2 sigma_deg^2 f^2), which at f = R is exp(-pi^2 / 1.86^2) = 5.8 %,
// i.e. R(Y) is the frequency the blur leaves at the edge of visibility.
// Support (Eq. 5.16): the thesis replaces Eq. 5.15 by sigma(L*) = max(1 - L*, 0) pixels, tuned to
// its headset (13.85 pixels per degree); what carries over to any display is its support, no blur
// where L* >= 1 (Y >= 0.111 cd/m2 with Y_n = 100; "L" is CIE lightness on its 0-100 scale, not a
// 0-1 value). Both forms are offered (`AcuitySigmaForm`); the default is Eq. 5.15 on the display's
// own pixels per degree, restricted to L* < 1.
// Kernel bound (section 5.3.2): kernel size s = 2 floor(3 sigma) + 1 (the rule the thesis cites
// from Nguyen 2007) with sigma <= 1 pixel gives s <= 7. Eq. 5.15 grows without bound as L* -> 0
// (R(Y) reaches 0 at Y = 6.5e-10 cd/m2), so sigma is capped at `max_sigma_px` (default 1, the
// thesis' bound; below the cap's luminance the blur stays at the cap). On the thesis' headset
// the cap binds only below L* = 0.09 (Y = 0.0097 cd/m2); on a desktop display at 42 pixels per
// degree Eq. 5.15 asks for 1.3-5 px wherever L* < 1, so the default blurs every dark pixel by the
// capped 1 px, and a larger max_sigma_px (up to 10) follows Eq. 5.15 further at
// 2 floor(3 sigma) + 1 taps per pass.
// Separable passes (section 5.3.1): horizontal with sigma from each pixel's lightness, then
// vertical with sigma from the lightness after the first pass (the thesis' step 3; Fig. 5.9's
// numbers use the first pass's sigma, `SecondPassSigma::original_lightness`). Edges are clamped.
// The full 2D blur, each pixel's own s x s kernel, is the reference the separable version is
// measured against (docs/PERCEPTION.md): the two agree exactly where sigma is uniform and differ
// at edges between dark and bright pixels (Fig. 5.9: 0.85 against 0.59 at the centre of a 3 x 3
// patch beside a bright corner).
#include <vector>

#include "core/display_spec.h"
#include "core/image.h"
#include "core/perception_settings.h"

namespace glarelab {

// Throws std::invalid_argument naming the field and its accepted range.
void validate_acuity_settings(const AcuitySettings& settings);

// Eq. 5.14, cycles per degree; negative below Y = 6.5e-10 cd/m2 (the formula as printed).
double larson_resolvable_frequency_cpd(double luminance_cd_m2);
// Pixels per degree at the screen centre from the display geometry: 1 / (2 atan(pitch / 2d)).
double display_pixels_per_degree(const DisplaySpec& display);
// The blur of a pixel of lightness L* (0 where L* >= 1), capped at max_sigma_px.
double acuity_sigma_px(double lightness, const AcuitySettings& settings, double pixels_per_degree);
// Nguyen's rule: kernel half-width floor(3 sigma); size 2 radius + 1.
int acuity_kernel_radius_px(double sigma_px);
// The sampled Gaussian exp(-k^2 / (2 sigma^2)), k = -radius..radius, normalised to sum 1; {1} for
// sigma = 0.
std::vector<double> acuity_kernel(double sigma_px);

// On a lightness plane (width x height, row-major): the separable passes and the 2D reference.
std::vector<double> blur_lightness_separable(const std::vector<double>& lightness, int width_px, int height_px,
                                             const AcuitySettings& settings, double pixels_per_degree);
std::vector<double> blur_lightness_2d(const std::vector<double>& lightness, int width_px, int height_px,
                                      const AcuitySettings& settings, double pixels_per_degree);

// The whole stage on a frame (alpha kept): separable (the thesis' method) or the 2D reference.
ImageRGBA apply_acuity_loss(const ImageRGBA& frame, const AcuitySettings& settings, double pixels_per_degree);
ImageRGBA apply_acuity_loss_2d_reference(const ImageRGBA& frame, const AcuitySettings& settings,
                                         double pixels_per_degree);

}  // namespace glarelab
