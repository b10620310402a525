#pragma once
// The hybrid eye: Ritschel et al. 2009's wave-optics PSF near the source, where its grid reaches,
// handed over to an analytic far field (Spencer 1995 or CIE 146, analytic_psf.h) beyond, on the
// display's pixels.
//
// Hand-over (display pixels at distance r from the source pixel, radii from degrees through the
// display geometry): a weight w(r) = 1 inside the inner radius r0, 0 outside the outer radius r1,
// a smoothstep in r between them (C1: no kink in the profile). The hybrid kernel is
//   H = s w P_wave + (1 - w) K_analytic,
// per channel, with P_wave the wave-optics PSF on display pixels (unit sum) and K_analytic the
// analytic kernel (display_glare_kernel.h). The scale s = sum(w K_analytic) / sum(w P_wave) gives
// the wave-optics part the energy the analytic model puts inside the hand-over, so H holds on the
// display exactly the energy K_analytic holds there, and with the analytic light that falls beyond
// the display the total is 1. Inside r0, H = s P_wave (the wave optics decides the shape); beyond
// r1, H = K_analytic exactly; the wave optics cannot reach farther than its grid, so r1 must lie
// inside the wave PSF's reach (wave_psf_reach_deg), else the hand-over is refused.
#include <array>
#include <stdexcept>

#include "glare/display_glare_kernel.h"
#include "glare/psf.h"

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

// The hand-over radii in display pixels (r = d tan(angle) / pitch).
struct HandoverPixels {
  double inner_px = 0.0;
  double outer_px = 0.0;
};
HandoverPixels handover_pixels(const HybridHandover& handover, const DisplayGeometry& geometry);

// Weight w of the wave-optics part at r_px display pixels from the source.
double handover_weight(double r_px, const HandoverPixels& handover);

// What a frame convolves is split in two (the convolution is linear): the far part (1 - w) K_analytic,
// fixed for a session (its spectrum is computed once), and the near part s w P_wave, made per frame
// from that frame's wave-optics PSF. near + far (centres aligned) is H.
DisplayKernel hybrid_far_kernel(const DisplayKernel& analytic, const HandoverPixels& handover);
// sum(w K_analytic) per channel (a one-channel kernel fills all three).
std::array<double, 3> analytic_energy_inside(const DisplayKernel& analytic, const HandoverPixels& handover);
// s w P_wave: the wave PSF (display scale, 1 or 3 channels, unit sum) weighted and scaled so each
// channel holds analytic_inside[c]; 3 channels. `scale_out` (optional) receives s per channel.
Psf hybrid_near_psf(const Psf& wave_display_psf, const std::array<double, 3>& analytic_inside,
                    const HandoverPixels& handover, std::array<double, 3>* scale_out = nullptr);

}  // namespace glarelab
