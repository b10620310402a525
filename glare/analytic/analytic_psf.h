#pragma once
// An analytic glare PSF over the whole visual field, radially symmetric about the point source:
// Spencer et al. 1995 (glare/analytic/spencer_psf.h) or CIE 146:2002 (glare/analytic/cie_glare_spread.h), with the observer's
// age and pigmentation. Values are densities per steradian, per linear Rec.709 channel; each
// channel has unit energy over the hemisphere (Spencer Eq. 3), counting the CIE peak.
//
// Spencer's halo f3 is chromatic: section 3.2 evaluates Eq. 7 at 50 wavelengths from 400 to 700 nm
// and converts them to a trichromatic colour. Here each channel's halo is the sum over those
// wavelengths weighted by the project's CIE 1931 functions in linear Rec.709 (glare/wave/cie_cmf.h, an
// equal-energy source), negative weights (spectral colours outside Rec.709) clamped to 0, each
// channel's weights summing to 1, so every channel's halo keeps unit volume. The sum is tabulated
// once per PSF (step 0.001 degrees, 4-point Lagrange interpolation: relative error ~1e-9).
// f0, f1, f2 and the CIE function are achromatic: the same in R, G and B.
#include <array>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "glare/analytic/spencer_psf.h"

namespace glarelab {

// Which model makes the glare of a frame (glare_spec.h, `[glare] model`): Ritschel et al. 2009's
// wave-optics eye, Spencer's or the CIE's analytic PSF, the hybrid of the wave-optics eye near
// the source and an analytic far field (glare/analytic/hybrid_psf.h), Luidolt 2020's glare kernel
// (glare/wave/luidolt_kernel.h), or the human eye (the default): the wave-optics eye's structure
// near the source with, on every ring around it, the light CIE 146:2002 gives the observer, and the
// CIE far field beyond (calibrated_near_psf, glare/analytic/hybrid_psf.h).
enum class GlareModel { ritschel, spencer, cie, hybrid, luidolt, human };
GlareModel parse_glare_model(const std::string& name);  // std::invalid_argument naming the choices
std::string to_string(GlareModel model);
// True for the models whose frames take the wave-optics eye's PSF (its pupil, particles, lashes):
// ritschel, hybrid and human.
constexpr bool uses_wave_optics(GlareModel model) {
  return model == GlareModel::ritschel || model == GlareModel::hybrid || model == GlareModel::human;
}

// The observer's eye as the analytic models see it (`[observer]` in the experiment file).
struct ObserverEye {
  ObserverEye() = default;
  // An eye of this age and pigmentation (CIE's age rule), or with a measured straylight.
  ObserverEye(double age, double pigment, std::optional<double> straylight = std::nullopt)
      : age_years(age), pigmentation(pigment), straylight_log_s(straylight) {}

  double age_years = 25.0;    // Spencer Eq. 10 and CIE 146; accepted 1-100
  double pigmentation = 0.5;  // CIE 146: 0 very dark eyes, 0.5 brown, 1 blue-green; accepted 0-1
  // The participant's measured straylight, log10(s) at 7 degrees (`[glare] straylight`): the CIE
  // function's wide-angle terms are scaled to it instead of by the age (glare/analytic/ring_straylight.h,
  // docs/STRAYLIGHT.md). Unset: the age's CIE eye.
  std::optional<double> straylight_log_s;
};
// std::invalid_argument naming the value and the accepted range.
void check_observer_eye(const ObserverEye& eye);

// Spencer's halo: the wavelengths of section 3.2 (50 from 400 to 700 nm) and their weights per
// channel (R, G, B), each channel's summing to 1.
struct HaloSpectrum {
  std::vector<double> wavelengths_nm;
  std::array<std::vector<double>, 3> channel_weights;
};
HaloSpectrum spencer_halo_spectrum();

class AnalyticPsf {
 public:
  static AnalyticPsf spencer(const spencer::Mixture& mixture);
  // Spencer's mixture for a regime, the adaptation luminance (used by `adaptive` only) and the age.
  static AnalyticPsf spencer(SpencerRegime regime, double adaptation_cd_m2, const ObserverEye& eye);
  static AnalyticPsf cie(const ObserverEye& eye);

  GlareModel model() const { return model_; }
  const spencer::Mixture& mixture() const { return mixture_; }
  const ObserverEye& eye() const { return eye_; }

  // Density per steradian of channel 0..2 (R, G, B) at angle_deg from the source.
  double per_sr(double angle_deg, int channel) const;
  // Energy of each channel that per_sr does not describe: it stays in the source point. CIE: one
  // minus the scattered light's integral over the hemisphere (computed once); Spencer: 0 (its
  // unscattered light is the f0 Gaussian).
  double peak_fraction() const { return peak_fraction_; }
  // True when the channels differ (a Spencer mixture with a halo).
  bool chromatic() const { return mixture_.f3 > 0.0; }
  // Angles (degrees) where the profile is not smooth: integration splits there (CIE: 0.1).
  std::vector<double> kink_angles_deg() const;
  // The radial profile the command line writes (`psf --profile-csv`): Spencer's whole P with its
  // halo at 568 nm (the wavelength of section 3.1.1's numbers); the CIE formula itself (the
  // scattered light, exact at every angle, also below its 0.1 degree range).
  double profile_per_sr(double angle_deg) const;
  // Spencer's P with the halo at one wavelength.
  double per_sr_at_wavelength(double angle_deg, double wavelength_nm) const;

 private:
  AnalyticPsf() = default;
  double halo_per_sr(double angle_deg, int channel) const;
  double cie_scattered_per_sr(double angle_deg) const;

  GlareModel model_ = GlareModel::spencer;
  spencer::Mixture mixture_;
  ObserverEye eye_;
  double cie_wide_angle_factor_ = 1.0;  // F of CIE 146's wide-angle terms (age or measured straylight)
  double peak_fraction_ = 0.0;
  // Spencer's halo per channel, tabulated from halo_table_start_deg_ in kHaloTableStepDeg steps.
  std::array<std::vector<double>, 3> halo_table_;
  double halo_table_start_deg_ = 0.0;
};

// Eq. 4's volume of a radial density over [from_deg, to_deg]: (pi^2 / 90) Int P sin(theta) dtheta,
// by adaptive Gauss-Kronrod quadrature (relative tolerance 1e-10), split at `breaks_deg`.
double radial_energy(const std::function<double(double)>& per_sr, double from_deg, double to_deg,
                     const std::vector<double>& breaks_deg = {});

}  // namespace glarelab
