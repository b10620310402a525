#pragma once
// Longitudinal chromatic aberration (LCA) of the human eye: the chromatic difference of refraction of
// Thibos, Ye, Zhang and Bradley, "The chromatic eye: a new reduced-eye model of ocular chromatic
// aberration in humans", Applied Optics 31(19):3594-3600, 1992 (the fit to the measured data, their
// Eq. 5 form):
//
//   Rx(lambda) = p - q / (lambda - c),  lambda in micrometres, Rx in dioptres,
//   p = 1.68524, q = 0.63346, c = 0.21410.
//
// Rx is a refraction: the spectacle-plane correction the eye needs at lambda, negative where the eye
// is myopic. Short wavelengths are refracted more, so the eye is myopic in the blue (Rx(400 nm) =
// -1.72 D) and hyperopic in the red (Rx(700 nm) = +0.38 D). Rx = 0 at lambda_0 = c + q / p =
// 589.99 nm, the sodium D line the paper refers its data to (`kLcaZeroWavelengthNm`).
//
// Where the constants come from: q and c are those of ISETCam (humanWaveDefocus.m,
// wvfLCAFromWavelengthDifference.m, both citing Thibos et al. 1992, p. 3596); the same paper's
// reduced eye (water-like index n(lambda) = a + b / (lambda - c), a = 1.320535, b = 0.004685,
// c = 0.214102, corneal radius r = 5.55 mm, n_D = 1.333) gives Rx = (n_D - n(lambda)) / (n_D r), i.e.
// q = b / (n_D r) = 0.63327 and p = (n_D - a) / (n_D r) = 1.68488, the fit's values to 0.03 %
// (tests/glare_chromatic_eye_test.cpp checks the two against each other). ISETCam's 1.7312 in place
// of p only moves the zero to 580 nm; differences between wavelengths, all that matters here, do not
// depend on p.
namespace glarelab {

inline constexpr double kThibosP_dioptres = 1.68524;
inline constexpr double kThibosQ_dioptre_um = 0.63346;
inline constexpr double kThibosC_um = 0.21410;
// c + q / p, in nanometres: where Rx = 0.
inline constexpr double kLcaZeroWavelengthNm = 1e3 * (kThibosC_um + kThibosQ_dioptre_um / kThibosP_dioptres);

// Thibos et al. 1992's chromatic difference of refraction Rx(lambda), dioptres. Throws
// std::invalid_argument (naming "glare/refraction/chromatic_eye") for lambda <= c (214.1 nm), where the fit has
// its pole.
double chromatic_refraction_dioptres(double wavelength_nm);

// The eye's excess power at wavelength_nm over that at reference_nm (dioptres): how much more the eye
// converges light of wavelength_nm than light of reference_nm, -(Rx(lambda) - Rx(lambda_ref)). Positive
// toward the blue. Added to a power error measured at reference_nm (glare/refraction/eye_refraction.h, positive =
// too much power) it gives the error at wavelength_nm.
double chromatic_power_excess_dioptres(double wavelength_nm, double reference_nm);

}  // namespace glarelab
