#pragma once
// The ciliary corona's radial lines in the human eye's frames ([glare] model "human", the default;
// docs/GLARE_OPTICS.md 9.9). The human eye's far field is CIE 146's smooth glare spread function;
// its wave-optics near field shows the corona's needles only out to its grid's reach (0.3-0.4
// degrees), while the corona lies at 2-8 degrees. Spencer et al. 1995 (section 3.2) draw the lines
// as a pattern of mean 1 multiplied into the smooth filter (glare/analytic/spencer_flare_lines.h),
// which would make the far kernel a lined one: a full-resolution convolution of the whole frame
// with it, where the smooth far field takes the two-level path (glare/analytic/analytic_two_level.h).
//
// The lines matter only around compact bright sources (glare/analytic/compact_sources.h; Spencer
// 2.2), so they are added per source instead, as what multiplying would add to the smooth veil:
//     C(d) = K(d) a(theta) (L_s(theta, phi) - 1),
// d the display offset from the source's centroid, theta its angle (as the display kernels take it,
// glare/analytic/display_glare_kernel.h), phi its azimuth, K the CIE 146 PSF per steradian times
// the pixel's solid angle (the far kernel's value there, at the pixel's centre), a(theta) the
// annulus (1 from 2 to 8 degrees, raised cosines to 0 at 1.5 and 9), and L_s Spencer's corona
// lines around a uniform disc (FlareLines::normalised: each line's box convolved in azimuth with
// the disc's chord profile, Spencer 2.2's superposition, in closed form). The disc is the source's
// blur: the disc whose tangential variance is the source's own (its pixels, each a square) plus the
// receiving pixel's square, since a pixel averages the lines over its width. Each ring of offsets
// (distance from the centroid rounded to a pixel) is normalised so that its sum of C is 0 (L_s
// divided by its K-weighted mean over the ring, as apply_flare_lines does): the frame's azimuthal
// means and its energy stay CIE 146's exactly. A source's energy times C is added to the frame's
// glare energy; the lines are the session's (the corona set of Spencer's lines, drawn from the
// session's seed by the counter-based generator), the same for every source, as one eye's corona.
//
// Sources much larger than 20 arcmin show no lines (Spencer 2.2): the closed form holds where the
// source is small beside its distance, so the lines fade out between source diameters of 0.75 and
// 1 degree, where the annulus' inner edge lies at 2 to 2.7 source diameters.
#include <cstddef>
#include <cstdint>
#include <deque>
#include <memory>
#include <mutex>
#include <vector>

#include "core/image.h"
#include "glare/analytic/analytic_psf.h"
#include "glare/analytic/compact_sources.h"
#include "glare/analytic/display_glare_kernel.h"
#include "glare/analytic/spencer_flare_lines.h"

namespace glarelab {

inline constexpr double kCoronaInnerDeg = 2.0;
inline constexpr double kCoronaOuterDeg = 8.0;
inline constexpr double kCoronaInnerEdgeDeg = 1.5;  // the annulus' weight is 0 inside
inline constexpr double kCoronaOuterEdgeDeg = 9.0;  // ... and outside
inline constexpr double kCoronaFadeFromSourceDeg = 0.75;
inline constexpr double kCoronaLargestSourceDeg = 1.0;

// a(theta): 1 from kCoronaInnerDeg to kCoronaOuterDeg, raised cosines to 0 at the edges.
double corona_annulus_weight(double angle_deg);
// The lines' share for a source of this disc diameter: 1 up to kCoronaFadeFromSourceDeg, a raised
// cosine to 0 at kCoronaLargestSourceDeg.
double corona_source_weight(double source_diameter_deg);

class CiliaryCorona {
 public:
  CiliaryCorona(const ObserverEye& eye, const DisplayGeometry& geometry, std::uint64_t seed);

  const FlareLines& lines() const { return lines_; }
  // The angle of the pixel on the line of sight, degrees.
  double degrees_per_pixel() const { return degrees_per_pixel_; }
  // Which groups of a frame are sources here (largest_diameter_px from kCoronaLargestSourceDeg).
  CompactSourceRule source_rule() const;
  // The diameter (degrees) of the disc that blurs this source's lines on the display: 8 times its
  // second moment plus 4/3 px^2 (the receiving pixel's square), square-rooted.
  double blur_diameter_deg(const CompactSource& source) const;
  // The source's own disc diameter in degrees.
  double source_diameter_deg(const CompactSource& source) const;

  // glare_energy's R, G, B += the source's energy x C over the pixels of the frame (alpha kept).
  // Each ring's sum is 0 over the whole ring, on the frame or beyond it. The result does not depend
  // on `threads`. A source of the same centroid and second moment on a frame of the same size as
  // one of the last few is only added, from the values kept for it (PatternCache). The pattern is
  // made for the centroid and second moment rounded to kPatternStepsPerPx, so sources that differ
  // only in their last digits share it.
  void add(const CompactSource& source, ImageRGBA& glare_energy, int threads = 2) const;

 private:
  // A source's C over the frame's pixels of its annulus' square, which add() multiplies by its
  // energy: a function of the source's centroid and second moment and of the frame's size alone.
  struct Pattern {
    double x_px = 0.0, y_px = 0.0, second_moment_px2 = 0.0;  // what it was made for
    int width_px = 0, height_px = 0;
    int from_x = 0, to_x = -1, from_y = 0, to_y = -1;  // the frame's pixels it covers (inclusive)
    std::vector<double> c;              // share x C, row by row over the covered pixels
    std::vector<unsigned char> adds;    // 1 where C is added (on the annulus, in a ring with lines)
    bool is_of(const CompactSource& source, int width, int height) const {
      return source.x_px == x_px && source.y_px == y_px && source.second_moment_px2 == second_moment_px2 &&
             width == width_px && height == height_px;
    }
    std::size_t bytes() const { return c.size() * sizeof(double) + adds.size(); }
  };
  // The patterns made last, the most recently used first. A session shows its lamps again and
  // again (the demo's reference lamp, in one of two places, in every trial), and a source met
  // again, bit for bit in the inputs above, is only added: the same values as made afresh.
  struct PatternCache {
    std::mutex mutex;
    std::deque<std::shared_ptr<const Pattern>> recent;
  };
  // A pattern is made for the source's centroid and second moment rounded to 1/1024 of a pixel (and
  // of a square pixel): one lamp shown at several luminances is found again with centroids that
  // differ in the ninth digit (the scene's floats scaled and rounded), and each pattern made anew
  // is a pass over the whole annulus on the way to the next trial's onset (docs/PERFORMANCE.md,
  // 2026-12-01). The rounding moves a source by at most 1/2048 px, far less than a pixel's average
  // over the lines resolves (a line is an arc minute wide: 0.7 px at 0.024 degrees per pixel).
  static constexpr double kPatternStepsPerPx = 1024.0;
  static CompactSource pattern_key(const CompactSource& source);
  static constexpr std::size_t kCoronaPatternsKept = 8;
  static constexpr std::size_t kCoronaPatternBytesKept = std::size_t{64} << 20;
  std::shared_ptr<const Pattern> pattern(const CompactSource& source, int width_px, int height_px, int threads) const;
  std::shared_ptr<const Pattern> make_pattern(const CompactSource& source, int width_px, int height_px,
                                              int threads) const;

  AnalyticPsf psf_;
  DisplayGeometry geometry_;
  FlareLines lines_;
  double degrees_per_pixel_ = 0.0;
  std::shared_ptr<PatternCache> patterns_ = std::make_shared<PatternCache>();
};

}  // namespace glarelab
