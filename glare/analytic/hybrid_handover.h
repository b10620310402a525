#pragma once
// The hybrid eye's hand-over annulus as a parameter (glare/analytic/hybrid_psf.h has the kernels): where the
// wave-optics PSF hands over to the analytic far field, the reach of the wave-optics grid, and the
// refusals. Plain parameter code, so the experiment-file reader (protocols/) can check a hand-over
// where it is written.
#include <stdexcept>

namespace glarelab {

struct HybridHandover {
  double inner_deg = 0.0;  // r0: the wave-optics PSF alone inside
  double outer_deg = 0.0;  // r1: the analytic model alone outside
};

class HandoverError : public std::invalid_argument {
 public:
  using std::invalid_argument::invalid_argument;
};

// The angle to which a spectral wave-optics PSF of grid_px pixels at reference_degrees_per_pixel
// (lambda_ref / aperture width) is defined in every channel: half the grid less one pixel, shrunk
// by the shortest wavelength of the chromatic blur (380 nm: its copy of the reference PSF is
// 575 / 380 times wider in angle, so the grid's edge comes in by that factor).
double wave_psf_reach_deg(int grid_px, double reference_degrees_per_pixel);

// The default hand-over for a reach: the annulus from half of 0.9 reach to 0.9 reach (an octave,
// so the blend is gradual), ending short of the grid's edge where the wave PSF's chromatic copies
// are cut off.
HybridHandover default_handover(double reach_deg);

// HandoverError naming both angles when outer > reach, inner >= outer or inner <= 0.
void check_handover(const HybridHandover& handover, double reach_deg);

// The same reach for a grid of grid_px pixels over an aperture grid aperture_width_mm wide
// (reference degrees per pixel lambda_ref / width, Ritschel's 575 nm).
double wave_psf_reach_for_aperture_deg(int grid_px, double aperture_width_mm);

}  // namespace glarelab
