#pragma once
// Spencer et al. 1995's flare lines (section 3.2, last two paragraphs): the smooth filters of
// Eqs. 5, 8 and 9 "lack the flare lines we expect ... because they are spatial averages over areas
// that cover many flare lines". Spencer adds them by "drawing random antialiased radial lines of
// random intensity in the range [0, 1]", one set for the ciliary corona (f1 and f2) and another
// for the lenticular halo (f3), normalises the pattern "so that it has an average pixel value of
// 1.0, and that each small neighborhood also has an average value of 1.0", and multiplies it into
// the smooth filter, which keeps the filter's macroscopic behaviour.
//
// Here, per set: kFlareLineCount lines, each a radial line from the source of visual-angle width
// kFlareLineWidthDeg, its azimuth uniform in [0, 2 pi) and its intensity uniform in [0, 1), both
// from the counter-based generator (core/random.h, stream spencer_flare_lines) and the session's
// seed, so a session's lines are reproducible. A line of width w at theta degrees from the source
// spans the azimuths phi_k +- w / (2 sin theta); on the display that is a wedge about the source
// pixel (central projection keeps azimuths about the line of sight). "Antialiased": a pixel takes
// the exact fraction of its square the wedge covers (polygon clipping), times the intensity, summed
// over the lines. "Each small neighbourhood": the radial lines thin out with the radius, so the
// neighbourhood that keeps the filter's profile is the ring: each ring of kernel pixels (those whose
// distance from the source rounds to one integer) is divided by its mean, weighted by the smooth
// kernel, so every ring keeps the smooth kernel's energy exactly and the azimuthal mean equals
// Spencer's P. That is the paper's "increasing the pixel intensity radially because the fraction of
// pixels in a streak decreases radially from the center".
//
// The source's size (section 2.2: "superimposing the fine flare lines coming from each part of an
// areal source eliminates the crisp pattern ... sources much larger than 20 minutes of arc did not
// have significant flare lines"): in a session nothing is modelled for it. The kernel is one source
// pixel's glare, and convolving the frame sums the lines of every pixel of a lamp, each shifted with
// its pixel, which is that superposition. For a uniform disc of angular diameter s the sum is, at
// theta >> s, the lines convolved in azimuth with the disc's chord profile (a semicircle of half
// width asin(sin(s / 2) / sin theta)); normalised() gives that closed form, which the tests check
// against the frame.
#include <cstdint>
#include <optional>
#include <vector>

#include "glare/analytic/display_glare_kernel.h"
#include "glare/analytic/spencer_psf.h"
#include "glare/wave/psf.h"

namespace glarelab {

enum class FlareLineSet : std::uint32_t { corona = 0, halo = 1 };

// Spencer draws "a number of lines to visually match Simpson's observations" and gives no count or
// width. The width is one minute of arc, the finest line a viewer resolves (on a coarser display the
// antialiasing spreads it over its pixel). The count follows section 2.2: with n lines of width w
// overlapping c = n w_s / (2 pi theta) deep (w_s the width blurred by the source, about w + 0.93 s
// for a disc of diameter s), the ring's contrast (standard deviation / mean) is sqrt(4 / (3 c)) for
// intensities uniform in [0, 1]; 600 lines give a 20 arcmin source about 0.2 at 1 degree (faint but
// present) and an 80 arcmin source about 0.1, while a point source's lines stand apart from about
// 2 degrees out. Both sets are drawn alike; they differ in their random draws.
inline constexpr int kFlareLineCount = 600;
inline constexpr double kFlareLineWidthDeg = 1.0 / 60.0;

struct FlareLine {
  double azimuth_rad = 0.0;  // [0, 2 pi)
  double intensity = 0.0;    // [0, 1)
};

class FlareLines {
 public:
  FlareLines(FlareLineSet set, std::uint64_t seed);

  FlareLineSet set() const { return set_; }
  const std::vector<FlareLine>& lines() const { return lines_; }  // sorted by azimuth

  // The azimuthal half width (radians) of every line at angle_deg from the source: w / (2 sin theta),
  // capped at pi (the line then covers the whole ring).
  static double half_width_rad(double angle_deg);

  // The un-normalised pattern on display pixel (dx, dy) of the source pixel: the sum over the lines
  // of intensity times the fraction of the pixel's square inside the line's wedge (the wedge's half
  // width taken at the pixel centre's angle from the source).
  double pixel_coverage(int dx, int dy, const DisplayGeometry& geometry) const;

  // The pattern at angle_deg from the source and azimuth phi, normalised to an azimuthal mean of
  // exactly 1 on every ring, around a uniform disc source of source_diameter_deg (0: a point): each
  // line's box in azimuth convolved with the disc's chord profile. 1 inside the source and where a
  // line covers the whole ring.
  double normalised(double angle_deg, double azimuth_rad, double source_diameter_deg = 0.0) const;

 private:
  FlareLineSet set_;
  std::vector<FlareLine> lines_;
  double intensity_sum_ = 0.0;
};

// The set that multiplies Spencer's component (0 f0, 1 f1, 2 f2, 3 f3): none for the unscattered
// core f0, the corona's for f1 and f2, the halo's for f3.
std::optional<FlareLineSet> flare_line_set_of_component(int component);

// Multiplies the kernel (one source pixel's glare, every channel) by the lines, normalised per ring
// and channel so that each ring's sum is what it was. A ring (a partial one, at the kernel's
// corners) that no line reaches keeps its smooth values. `threads` splits the rows (the result does
// not depend on it).
void apply_flare_lines(DisplayKernel& kernel, const FlareLines& lines, const DisplayGeometry& geometry, int threads = 2);

// Spencer's kernel with flare lines for a mixture: f0 smooth, f1 and f2 each times the corona's
// lines, f3 times the halo's, weighted by the mixture (3 channels when it has a halo, else 1).
DisplayKernel spencer_flare_kernel(const spencer::Mixture& mixture, const DisplayGeometry& geometry, int half_width_px,
                                   int half_height_px, std::uint64_t seed, int threads = 2);

// The same as a unit-sum PSF image of size_px (even) on a flat display whose centre pixel
// subtends degrees_per_pixel (`psf --model spencer --flare-lines`; glare/analytic/display_psf_image.h).
Psf spencer_flare_psf_image(const spencer::Mixture& mixture, double degrees_per_pixel, int size_px, std::uint64_t seed,
                            int threads = 2);

}  // namespace glarelab
