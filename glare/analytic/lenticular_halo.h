#pragma once
// The lenticular halo of the eye model's lens-fibre gratings over the whole display, for the human
// eye (`[glare] model = "human"`, docs/GLARE_OPTICS.md 9.8). The wave-optics grid of a session
// (256 px over 10 mm: 39 um aperture pixels, +-0.42 degrees) neither resolves the fibres (10.85 um
// period) nor reaches the halo's 3 degrees, and the near part is calibrated to CIE 146 ring by ring,
// which would flatten a ring even where the grid reached. So the halo is computed here from the
// gratings' geometry (glare/eye/lens_model.h: patches of K parallel fibre membranes of period e,
// membrane width f e and transmittance t, in the cortex annulus):
//   - where: the first order of a grating of period e lies at sin(theta) = lambda / e (Spencer 1995
//     section 2.1, Eq. 4; Ritschel 2009 section 3.3): 3.0 degrees at 568 nm for e = 10.85 um, red
//     outside blue. Across the membranes a patch of K periods has the far field of K slits,
//       I(x) ~ [sin(K pi x) / (K sin(pi x))]^2 [sin(pi f x) / (pi f x)]^2,   x = e sin(theta) / lambda,
//     whose first-order lobe (x in [0.5, 1.5]) is the ring's radial profile (FWHM 0.886 lambda /
//     (K e cos theta): 0.33 degrees for K = 8, Mellerio and Palmer's 0.35). Along the membranes the
//     patch is 0.6 mm long: 0.05 degrees, tangential to the ring, so it does not widen it. The patches
//     are oriented at random over the annulus, so their lobes sum to a ring.
//   - how much: the light falling on a patch that a binary amplitude grating sends into its +-1
//     orders, 2 ((1 - t) sin(pi f) / pi)^2 (its Fourier coefficients), times the patches' area
//     inside the pupil over the pupil's area. A pupil that hides the annulus (under 3 mm: Spencer
//     2.1, "a beam less than 3 mm in diameter can pass through the clear portion") has no halo.
//     The halo's light is taken from the source's own point, as Spencer 3.1.1 diverts f3 from the
//     central peak, so the kernel keeps unit energy and CIE 146's scattered light is unchanged at
//     every other angle.
// Only the first orders are kept: with f = 0.5 the even orders vanish and the third carries 1/9 of
// the first, at 9 degrees. The source is a frame's white, D65: each channel sums the rings of D65's
// wavelengths (380-780 nm) weighted by the CIE 1931 functions in linear Rec.709 with their signs, so
// a white lamp's Rec.709 luminance is the V(lambda)-weighted ring, red's ring lies outside blue's,
// and the colours outside Rec.709's gamut are moved towards grey at their own luminance (no
// channel negative); each channel's ring has unit energy.
#include <array>
#include <cstdint>
#include <memory>
#include <vector>

#include "core/image.h"
#include "glare/analytic/display_glare_kernel.h"
#include "glare/analytic/display_kernel_convolution.h"
#include "glare/eye/aperture_geometry.h"

namespace glarelab {

struct EyeParameters;

// The fibre gratings as the halo sees them (glare/eye/eye_parameters.h, lens_grating_*).
struct HaloGratings {
  double period_mm = 0.000568 / 0.052335956242943835;  // e: 3 degrees at 568 nm
  int lines_per_patch = 8;                              // K
  double line_width_fraction = 0.5;                     // f
  double transmittance = 0.5;                           // t
};
HaloGratings halo_gratings(const EyeParameters& parameters);

// 2 ((1 - t) sin(pi f) / pi)^2: the share of the light on a patch that goes into its +-1 orders.
double first_order_efficiency(const HaloGratings& gratings);

// The share of the light through a pupil of pupil_diameter_mm (centred on the axis) that the
// gratings send into the halo: the membranes' area inside the pupil (each line's length inside the
// disc times its width) over f gives the patches' area there. 0 when no line reaches into the pupil.
double lenticular_halo_energy(const std::vector<ApertureLine>& grating_lines, const HaloGratings& gratings,
                              double pupil_diameter_mm);

// The ring's radial density per steradian for unit halo energy.
class LenticularHalo {
 public:
  explicit LenticularHalo(const HaloGratings& gratings);

  // asin(lambda / e) in degrees: where the first order lies.
  double first_order_deg(double wavelength_nm) const;
  // One wavelength's ring, per steradian (unit energy over the sphere).
  double per_sr_at_wavelength(double angle_deg, double wavelength_nm) const;
  // A white source's ring in channel 0..2 (R, G, B), per steradian, unit energy per channel.
  double per_sr(double angle_deg, int channel) const;
  // The angles outside which every channel is 0.
  double inner_deg() const { return table_start_deg_; }
  double outer_deg() const;

 private:
  HaloGratings gratings_;
  double lobe_integral_ = 0.0;  // Int_0.5^1.5 I(x) dx
  double table_start_deg_ = 0.0;
  std::array<std::vector<double>, 3> table_;  // per channel, kHaloTableStepDeg steps
};

// The ring integrated over each display pixel's solid angle (as glare/analytic/display_glare_kernel.h
// does for the analytic PSFs), 3 channels, out to the ring's outer angle: each channel sums to the
// halo's energy that lands on the pixels (1 less what falls beyond the kernel's reach, 0).
DisplayKernel lenticular_halo_kernel(const LenticularHalo& halo, const DisplayGeometry& geometry, int threads = 2);

// A session's halo on frames of one size: the kernel's spectrum made once, the last frame's ring
// kept (a dynamic interval brings one composed frame many times while the pupil, and so the halo's
// energy, moves: the ring is linear in that energy, so only the sum is redone).
class LenticularHaloGlare {
 public:
  LenticularHaloGlare(const LenticularHalo& halo, const DisplayGeometry& geometry, int width_px, int height_px,
                      int threads = kGlareCpuThreads);
  // glared_energy += halo_energy (ring * source - source), per channel: the ring's light, taken from
  // the source's own pixel. Energies per pixel (glare/analytic/pixel_solid_angle.h).
  void add(const ImageRGBA& source_energy, double halo_energy, ImageRGBA& glared_energy);
  // The ring of unit energy convolved with `source_energy` (no light taken from the source), kept
  // until the next source. `source_token`: non-zero names the source's pixels for the caller (the
  // same token, the same pixels), so that the kept ring of that token is taken without comparing
  // them; 0: compared.
  const ImageRGBA& ring(const ImageRGBA& source_energy, std::uint64_t source_token = 0);
  long long convolutions_computed() const { return convolutions_computed_; }
  int width_px() const { return width_px_; }
  int height_px() const { return height_px_; }

 private:
  int width_px_ = 0, height_px_ = 0;
  std::unique_ptr<DisplayKernelConvolution> convolution_;
  ImageRGBA last_source_, last_ring_;
  bool kept_ = false;
  std::uint64_t kept_token_ = 0;  // the caller's token for last_source_ (0: none)
  long long convolutions_computed_ = 0;
};

}  // namespace glarelab
