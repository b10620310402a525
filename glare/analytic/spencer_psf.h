#pragma once
// The analytic point-spread function of Spencer, Shirley, Zimmerman and Greenberg 1995, section 3.1
// (after Vos 1984 and Hemenger 1992): a radial density P(theta) per steradian over the visual
// field, theta the angle from the point source in degrees, of unit volume by Eq. 4,
//   (pi^2 / 90) Int_0^90 P(theta) sin(theta) dtheta = 1.
// Components (each of unit volume, tests/glare_spencer_psf_test.cpp):
//   f0 = 2.61e6 exp(-(theta / 0.02)^2)          unscattered Gaussian core
//   f1 = 20.91 / (theta + 0.02)^3               ciliary corona, theta^-3
//   f2 = 72.37 / (theta + 0.02)^2               veiling glare, theta^-2
//   f3 = 436.9 (568 / lambda) exp(-19.75 (theta - 3 lambda / 568)^2)   lenticular halo (Eq. 7)
// The printed Eq. 7 drops Hemenger's 19.75 (Eq. 6) from the exponent. It must be there: the halo
// of Eq. 6 has an angular width of 0.35 degrees, and 436.9 is exactly the constant that gives the
// Gaussian exp(-19.75 (theta - 3)^2) unit volume by Eq. 4:
//   (pi^2 / 90) * sqrt(pi / 19.75) * sin(3 deg) * 436.9 = 0.10966 * 0.39882 * 0.052336 * 436.9 = 1.0000,
// while without 19.75 the same sum is 4.44. For another wavelength the ring moves to
// 3 lambda / 568 degrees and 568 / lambda keeps sin(theta) ~ theta times the height constant.
// Mixtures: photopic P_p (Eq. 5), mesopic P_m (Eq. 8), scotopic P_s (Eq. 9); the age term of Eq. 10
// moves 6.9e-9 A^4 of the weight from f0 to f2.
#include <string>

namespace glarelab {

// Which of the paper's mixtures a frame uses. `adaptive` picks by the adaptation luminance
// (scotopic below 0.01 cd/m2, mesopic to 3, photopic above, the bands of section 3.1 after
// Mesopic vision [23]) and blends smoothly across each boundary (see adaptive_mixture()).
enum class SpencerRegime { photopic, mesopic, scotopic, adaptive };

SpencerRegime parse_spencer_regime(const std::string& name);  // std::invalid_argument naming the choices
std::string to_string(SpencerRegime regime);

namespace spencer {

double f0_per_sr(double angle_deg);
double f1_per_sr(double angle_deg);
double f2_per_sr(double angle_deg);
double f3_per_sr(double angle_deg, double wavelength_nm);

// The wavelength at which section 3.1.1 states its numbers (Mallero and Palmer's 568 nm).
inline constexpr double kHaloReferenceWavelengthNm = 568.0;
// The halo's peak angle for a wavelength: 3 lambda / 568 degrees.
double halo_peak_deg(double wavelength_nm);

// Weights of f0..f3 in a mixture; they sum to 1, so the mixture has unit volume.
struct Mixture {
  double f0 = 0.0, f1 = 0.0, f2 = 0.0, f3 = 0.0;
};

inline constexpr Mixture kPhotopic{0.384, 0.478, 0.138, 0.0};  // Eq. 5
inline constexpr Mixture kMesopic{0.368, 0.478, 0.138, 0.016};  // Eq. 8
inline constexpr Mixture kScotopic{0.282, 0.478, 0.207, 0.033};  // Eq. 9

// Eq. 10's age term, 6.9e-9 A^4, moved from f0 to f2. Section 3.1.2 gives it for P_p and says P_m
// and P_s behave alike, so it is applied to every mixture. Past about 86 years (photopic) the
// term exceeds f0's weight and Eq. 10 would make the PSF negative; the shift is then capped at
// f0's whole weight (all light scattered, the cataract limit the section mentions).
Mixture with_age(const Mixture& mixture, double age_years);

// Adaptation luminance bounds of the regimes (cd/m2) and the half width of the blend around each,
// in decades: the mixture moves from one regime's to the next by a smoothstep in log10 luminance
// over boundary +- 0.25 decades, so a slowly darkening scene never jumps (the weights, and so the
// PSF, are C1 in log luminance).
inline constexpr double kScotopicBelowCdM2 = 0.01;
inline constexpr double kPhotopicAboveCdM2 = 3.0;
inline constexpr double kRegimeBlendHalfWidthDecades = 0.25;

// The mixture of a regime at an adaptation luminance (used only by `adaptive`), before the age term.
Mixture regime_mixture(SpencerRegime regime, double adaptation_cd_m2);

// The whole P(theta) of a mixture at one wavelength (f3's).
double mixture_per_sr(const Mixture& mixture, double angle_deg, double wavelength_nm);

}  // namespace spencer
}  // namespace glarelab
