#pragma once
// Luidolt 2020's glare kernel ("Perception of Light in Virtual Reality", section 5.2.2 and 6.3):
//   P(x, y)  static particles: a binary random dot pattern of `particle_count` opaque dots of
//            diameter `particle_diameter_mm` (1000 of 0.042 mm, section 5.2.4) over the aperture
//            texture, whose side spans the thesis' largest pupil (8 mm, section 5.2.1 ii);
//   F_C      the static Fresnel term, Eq. 5.6: exp(i pi (x^2 + y^2) / (lambda d)), lambda = 575 nm,
//            d = 24 mm;
//   A(x, y)  the pupil, a binary disc of the current (tracked) diameter;
//   L_C = P F_C A (Eq. 5.7), T_C = FFT(L_C) (Eq. 5.10), M = |T_C / N|^2 / (lambda d)^2 (Eq. 5.11);
//   S_XYZ(x, y) = 1/(k+1) sum_i XYZ(phi_i) M(x lambda / phi_i, y lambda / phi_i),
//            phi_i = 380 + (i / k) (770 - 380) nm (Eqs. 5.12, 5.13), then linear Rec.709;
//   and the added bright centre (section 6.3.2): the kernel's pixel (0, 0) is overwritten (Eq. 5.10's
//   reason the added constant does not matter) by a single bright pixel.
//
// Choices the thesis leaves open, each said once here and in docs/GLARE_OPTICS.md ("Luidolt 2020's
// glare kernel"):
//  - Units: the thesis evaluates Eq. 5.6 on normalised device coordinates; here x and y are metres
//    on the aperture texture (side `aperture_width_mm`), the only reading in which lambda and d
//    carry their physical meaning.
//  - The centre's brightness is not given as a number. Here the centre pixel holds the light the
//    particles leave unscattered: the fraction of the pupil's area no particle covers. The rest of
//    the kernel (the Eq. 5.12 sum without its pixel (0, 0)) holds the covered fraction, so each
//    channel sums to 1 (a convolution that keeps the frame's energy).
//  - Pixels of S_RGB below 0 (spectral colours outside Rec.709) are clamped to 0 before the
//    normalisation, as the project's other spectral PSFs do (glare/wave/spectral_accumulation.h).
//
// Sampling condition of Eq. 5.6 (docs/GLARE_OPTICS.md derives it): the phase pi r^2 / (lambda d)
// changes by about 2 pi r dx / (lambda d) between neighbouring samples at radius r; it matters only
// where A transmits, so at the pupil's edge r = D/2 the step must stay below pi:
//   dx < lambda d / D, i.e. N > W D / (lambda d).
// (With dx at the limit the DFT's angular field N lambda / W equals D / d, the angle the pupil's own
// shadow fills: the chirp's highest frequency lands on the grid's edge.) A coarser grid is refused,
// or, with `enlarge_grid`, enlarged to the smallest even 2,3,5-smooth size that meets it, and the
// result says so.
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

#include "glare/wave/psf.h"

namespace glarelab {

struct LuidoltKernelOptions {
  int particle_count = 1000;            // section 5.2.4 (van den Berg et al. 2005's 1000)
  double particle_diameter_mm = 0.042;  // section 5.2.4, found "feasible" by the thesis
  double wavelength_nm = 575.0;         // Eq. 5.6: the mean of the human spectrum
  double distance_mm = 24.0;            // Eq. 5.6: pupil to retina, "the human focal length"
  double aperture_width_mm = 8.0;       // the texture's side: the thesis' largest pupil (2-8 mm)
  int wavelength_count = 32;            // k + 1 of Eqs. 5.12-5.13 (>= 2)
  int grid_px = 256;                    // N asked for; the sampling condition may demand more
  bool enlarge_grid = true;             // false: a grid that aliases Eq. 5.6 throws LuidoltSamplingError
  int largest_grid_px = 8192;           // an enlargement past this throws LuidoltSamplingError
};

// A configuration whose Fresnel term the grid would alias, refused (message names the numbers).
class LuidoltSamplingError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Eq. 5.6's sampling condition for a pupil of pupil_diameter_mm on `options`' texture.
struct LuidoltSampling {
  double max_pixel_mm = 0.0;        // lambda d / D: the largest sample spacing whose edge step is < pi
  int required_grid_px = 0;         // the smallest even 2,3,5-smooth N with W / N below it
  double edge_phase_step_rad = 0.0; // the step at the pupil's edge on the grid asked for
  bool aliased = false;             // edge_phase_step_rad >= pi on the grid asked for
};
LuidoltSampling luidolt_sampling(double pupil_diameter_mm, const LuidoltKernelOptions& options);

// The particle pattern P of the thesis' pre-processing step: centres uniform over the texture
// (mm, origin at its centre), drawn from `seed`'s eye-model stream, channel EyeChannel::luidolt_particles
// (glare/eye/eye_random_channels.h), particle i from counter i (the first n of a larger count are the same).
struct LuidoltParticle {
  double x_mm = 0.0, y_mm = 0.0;
};
std::vector<LuidoltParticle> luidolt_particles(std::uint64_t seed, const LuidoltKernelOptions& options);

// P A on an N x N grid (pixel centres at (i + 0.5) W / N - W / 2): 1 where the pupil transmits and no
// particle covers the pixel's centre, else 0 (the thesis' binary masks).
std::vector<double> luidolt_aperture_mask(const std::vector<LuidoltParticle>& particles, double pupil_diameter_mm,
                                          int grid_px, const LuidoltKernelOptions& options);

struct LuidoltKernel {
  Psf psf;                          // R, G, B, each sums to 1, centred at (N/2, N/2), lambda / W rad per pixel
  int grid_px = 0;                  // N used (options.grid_px or the enlargement)
  std::string sampling_note;        // non-empty when the grid was enlarged: what and why
  double pupil_diameter_mm = 0.0;
  double pupil_pixels = 0.0;        // samples inside the pupil (A = 1)
  double covered_fraction = 0.0;    // of those, the fraction particles cover
  double centre_share = 0.0;        // the bright centre's share of each channel: 1 - covered_fraction
  // Eq. 5.11 before anything is overwritten: sum_xy M and M at the DC pixel (both in 1/m^2).
  double monochromatic_sum_per_m2 = 0.0;
  double monochromatic_dc_per_m2 = 0.0;
  double clamped_negative_fraction[3] = {0.0, 0.0, 0.0};  // per channel, of its positive energy
};

// The kernel for one pupil. Throws std::invalid_argument for options or a pupil outside their ranges
// (pupil in (0, aperture_width_mm]), LuidoltSamplingError as above, ClosedApertureError when every
// pupil sample is covered.
LuidoltKernel luidolt_kernel(double pupil_diameter_mm, std::uint64_t seed, const LuidoltKernelOptions& options);

// One sentence for the record: the particles, the Fresnel term, the texture and the spectral sum.
std::string luidolt_description(const LuidoltKernelOptions& options);

// Eq. 5.12's sum for one-channel M: the XYZ image (planes X, Y, Z, each N x N) of
// 1/(k+1) sum_i XYZ(phi_i) M(x lambda / phi_i, ...), M read by bilinear interpolation about (N/2, N/2),
// zero outside. Without a Jacobian: the thesis scales the copies' coordinates, not their values.
std::vector<double> luidolt_spectral_xyz(const std::vector<double>& monochromatic, int grid_px, double wavelength_nm,
                                         int wavelength_count);

}  // namespace glarelab
