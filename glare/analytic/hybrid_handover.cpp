#include "glare/analytic/hybrid_handover.h"

#include <cmath>
#include <sstream>
#include <string>

#include "glare/wave/psf.h"
#include "glare/cpu/psf.h"

namespace glarelab {
namespace {

// The chromatic blur's shortest wavelength and its reference (glare/wave/spectral_psf.h, Ritschel et al. 2009
// section 5): the 380 nm copy of the reference PSF is read at theta * 575 / 380, so it leaves the
// grid 575 / 380 times nearer the centre than the reference does.
constexpr double kShortestBlurWavelengthNm = 380.0;
constexpr double kBlurReferenceWavelengthNm = 575.0;

std::string angle_text(double degrees) {
  std::ostringstream out;
  out.precision(4);
  out << degrees << " deg";
  return out.str();
}

}  // namespace

double wave_psf_reach_deg(int grid_px, double reference_degrees_per_pixel) {
  return (0.5 * grid_px - 1.0) * reference_degrees_per_pixel * (kShortestBlurWavelengthNm / kBlurReferenceWavelengthNm);
}

HybridHandover default_handover(double reach_deg) {
  const double outer_deg = 0.9 * reach_deg;
  return {0.5 * outer_deg, outer_deg};
}

void check_handover(const HybridHandover& handover, double reach_deg) {
  const std::string annulus = "the hand-over from " + angle_text(handover.inner_deg) + " to " + angle_text(handover.outer_deg);
  if (!std::isfinite(handover.inner_deg) || !std::isfinite(handover.outer_deg) || handover.inner_deg <= 0.0)
    throw HandoverError(annulus + " must start at a finite angle above 0 deg");
  if (handover.inner_deg >= handover.outer_deg)
    throw HandoverError(annulus + " is empty: its inner angle must lie below its outer angle");
  if (handover.outer_deg > reach_deg)
    throw HandoverError(annulus + " ends beyond the wave-optics PSF's reach, " + angle_text(reach_deg) +
                        " (half its grid less one pixel, at the chromatic blur's 380 nm): a larger grid or a "
                        "narrower aperture grid reaches farther");
}

double wave_psf_reach_for_aperture_deg(int grid_px, double aperture_width_mm) {
  return wave_psf_reach_deg(grid_px, psf_degrees_per_pixel(kReferenceWavelengthNm, aperture_width_mm));
}

}  // namespace glarelab
