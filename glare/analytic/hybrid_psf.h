#pragma once
// The hybrid eye: Ritschel et al. 2009's wave-optics PSF near the source, where its grid reaches,
// handed over to an analytic far field (Spencer 1995 or CIE 146, glare/analytic/analytic_psf.h) beyond, on the
// display's pixels.
//
// Hand-over (display pixels at distance r from the source pixel, radii from degrees through the
// display geometry): a weight w(r) = 1 inside the inner radius r0, 0 outside the outer radius r1,
// a smoothstep in r between them (C1: no kink in the profile). The hybrid kernel is
//   H = s w P_wave + (1 - w) K_analytic,
// per channel, with P_wave the wave-optics PSF on display pixels (unit sum) and K_analytic the
// analytic kernel (glare/analytic/display_glare_kernel.h). The scale s = sum(w K_analytic) / sum(w P_wave) gives
// the wave-optics part the energy the analytic model puts inside the hand-over, so H holds on the
// display exactly the energy K_analytic holds there, and with the analytic light that falls beyond
// the display the total is 1. Inside r0, H = s P_wave (the wave optics decides the shape); beyond
// r1, H = K_analytic exactly; the wave optics cannot reach farther than its grid, so r1 must lie
// inside the wave PSF's reach (wave_psf_reach_deg), else the hand-over is refused.
//
// Continuity across the hand-over (tests/glare_hybrid_psf_test.cpp, docs/GLARE_OPTICS.md): take
// the azimuthal mean of each kernel on 1-pixel rings (ring k: pixels whose distance rounds to k)
// for H, A = s P_wave and K = K_analytic, over the rings from floor(r0) to ceil(r1). The largest
// step |ln H_k+1 - ln H_k| between adjacent rings is at most
//   max(largest step of A, largest step of K) + c(rho) / (r1 - r0),
// rho the largest ratio A_k / K_k or K_k / A_k over those rings and
//   c(rho) = max over t in [0, 1] of 6 t (1 - t) (rho - 1) / (1 + (rho - 1) (3 t^2 - 2 t^3)),
// the steepest slope of ln(1 - S + S rho) in t for the smoothstep S: the log slope the blend of two
// profiles rho apart adds to theirs (d ln H / dr = (w A' + (1 - w) K' + w' (A - K)) / H, whose
// first part is bounded by the two models' own log slopes). For rho near 1, c(rho) is about
// 1.5 ln(rho): the blend spreads the models' level difference over the annulus. A hard switch from
// A to K instead jumps by the whole ln(rho) in one ring.
#include <array>
#include <stdexcept>

#include "glare/analytic/display_glare_kernel.h"
#include "glare/analytic/hybrid_handover.h"
#include "glare/wave/psf.h"

namespace glarelab {

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
// HandoverError when the outer radius passes the grid's half less one pixel (the weight must reach
// 0 where the wave PSF is known) or the weighted wave PSF holds no light.
Psf hybrid_near_psf(const Psf& wave_display_psf, const std::array<double, 3>& analytic_inside,
                    const HandoverPixels& handover, std::array<double, 3>* scale_out = nullptr);

// The human eye's near part (GlareModel::human; docs/GLARE_OPTICS.md, 6a): the wave-optics PSF
// scaled ring by ring instead of by one s. Ring k holds the display pixels whose distance from the
// source rounds to k; on it the near part is g_k w P_wave with
//   g_k = sum_ring_k(w K_analytic) / sum_ring_k(w P_wave)   (per channel),
// so every ring of near + far, s.t. far = (1 - w) K_analytic, holds exactly the light K_analytic
// holds there: the azimuthal mean is the analytic model's (CIE 146:2002 for the observer) on every
// ring, and the energy rule of hybrid_near_psf holds ring by ring. Within a ring the wave optics
// keeps its structure (particles' speckle, the corona's needles, lashes, the chromatic blur's
// colour between channels); across rings the analytic model sets the level. Why: the wave-optics
// eye of Ritschel et al. 2009 scatters 8-40x less light than human eyes between 0.5 and 4 degrees
// (Spencer's P_p), and one s for the whole hand-over leaves it about 10x above the analytic kernel
// inside it, while CIE 146's glare spread function is the measured amount of stray light at each
// angle and, as the standard takes it, does not depend on the pupil. A ring whose wave PSF holds
// no light in a channel gets w K_analytic there. `analytic` is the unweighted analytic kernel on
// the same display pixels (1 or 3 channels), reaching at least the outer radius; HandoverError
// as hybrid_near_psf, and when the kernel is too small.
Psf calibrated_near_psf(const Psf& wave_display_psf, const DisplayKernel& analytic, const HandoverPixels& handover);

}  // namespace glarelab
