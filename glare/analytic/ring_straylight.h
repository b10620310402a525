#pragma once
// The straylight a ring of light sends into the centre of the field it surrounds, for an eye that
// scatters with the CIE 146:2002 glare spread function (glare/analytic/cie_glare_spread.h), and the
// CIE eye that has a chosen (measured) straylight.
//
// The straylight parameter (van den Berg 1991; Franssen, Coppens & van den Berg 2006) is
//   s(theta) = theta^2 L_eq / E_glare = theta^2 GSF(theta)   [deg^2 / sr],
// theta in degrees, GSF the veiling luminance per glare illuminance per steradian. A uniform ring
// of luminance L from theta_in to theta_out puts, at the centre,
//   L_eq = L * integral GSF(theta) dOmega,  dOmega = 2 pi theta_rad dtheta_rad
// (small angles: sin theta differs from theta by 0.5 % at 10 degrees). With s constant over the
// ring this is L * s * k, k = 2 pi (pi / 180)^2 ln(theta_out / theta_in), so the ring measures the
// log-angle mean of s over the ring: s_ring = integral s(theta) dtheta / theta / ln(theta_out / theta_in).
//
// Each function takes the CIE function's wide-angle factor F (cie146_age_factor(age) for an eye of
// that age; cie146_factor_for_straylight for a measured one).
namespace glarelab {

// The angle a measured straylight refers to: the mean angle of the compensation-comparison ring
// (5-10 degrees) and of the age norm.
inline constexpr double kStraylightReferenceAngleDeg = 7.0;

// The eye's straylight parameter at one angle, log10(theta^2 GSF(theta)).
double cie146_straylight_log10(double angle_deg, double wide_angle_factor, double pigmentation);

// L_eq / L_ring at the ring's centre: the fraction of the ring's luminance the eye scatters onto
// the test field (Simpson's rule in ln theta, 512 intervals).
double cie146_ring_veil_fraction(double inner_deg, double outer_deg, double wide_angle_factor, double pigmentation);

// The wide-angle factor F whose CIE function has straylight 10^log_s at `angle_deg`: the
// function's shape kept, its age-dependent terms (5 / theta^2 + 0.1 p / theta) scaled, as CIE 146
// scales them with age. std::invalid_argument when even F = 0 gives more straylight than asked
// (log_s below the function's age-independent terms: about 0.17 at 7 degrees).
double cie146_factor_for_straylight(double log_s, double angle_deg, double pigmentation);

}  // namespace glarelab
