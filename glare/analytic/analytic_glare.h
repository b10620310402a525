#pragma once
// The analytic glare of a session's frames on one display (Spencer 1995 or CIE 146): the model's
// kernel on the display's pixels (glare/analytic/display_glare_kernel.h, twice the frame so every pixel reaches
// every other) and its FFT convolution (glare/analytic/display_kernel_convolution.h). For the hybrid eye this is
// the far field, (1 - w) K (glare/analytic/hybrid_psf.h), and the wave-optics near part is the caller's.
//
// Spencer's adaptive regime changes the mixture with the adaptation luminance: the kernels of f0,
// f1, f2 and the halo f3 are integrated once, their spectra kept, and a new mixture is a weighted
// sum of spectra (no new integration, no new kernel FFT). A fixed regime or CIE has one kernel.
//
// Two convolutions: `full` (glare/analytic/display_kernel_convolution.h, an FFT of twice the frame: the reference,
// float32 within 3e-7 of float64) and `two_level` (glare/analytic/analytic_two_level.h: the sharp centre exactly,
// the smooth far field at a quarter of the resolution): its error on a 1920 x 1080 frame is within
// 1e-3 of the peak and 1e-4 L2 of the float64 full convolution (docs/PERFORMANCE.md), below what a
// 10-bit display shows. `automatic` (the default) takes two_level for frames of at least
// kTwoLevelMinimumPixels and full below, where the full FFT is at most 1280 x 960 and exact.
//
// Spencer's flare lines (glare/analytic/spencer_flare_lines.h, `flare_lines`): the kernels of f1
// and f2 are multiplied by the corona's lines and f3's by the halo's, each ring keeping its energy;
// a fixed regime then also keeps its components (weighted by its mixture). The far field is no
// longer smooth, so `automatic` takes the full convolution and `two_level` is refused.
#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>

#include "core/image.h"
#include "glare/analytic/analytic_psf.h"
#include "glare/analytic/analytic_two_level.h"
#include "glare/analytic/display_kernel_convolution.h"
#include "glare/analytic/hybrid_psf.h"

namespace glarelab {

enum class AnalyticConvolution { automatic, full, two_level };
inline constexpr long long kTwoLevelMinimumPixels = 640LL * 480LL;
std::string to_string(AnalyticConvolution convolution);

struct AnalyticGlareOptions {
  GlareModel model = GlareModel::spencer;  // spencer or cie
  SpencerRegime regime = SpencerRegime::adaptive;
  ObserverEye eye;
  DisplayGeometry geometry;
  int width_px = 0, height_px = 0;  // the frames
  std::optional<HandoverPixels> handover;  // set: the hybrid's far part
  AnalyticConvolution convolution = AnalyticConvolution::automatic;
  TwoLevelSplit split;  // the two-level path's near radii and decimation
  bool flare_lines = false;        // Spencer only: the flare lines of section 3.2
  std::uint64_t flare_seed = 0;    // their draws (the session's seed)
  // A frame brought again (bit for bit, same kernel) gets the kept glare; off where a benchmark
  // times the convolution itself.
  bool keep_repeated_frame = true;
};

class AnalyticGlare {
 public:
  explicit AnalyticGlare(const AnalyticGlareOptions& options, int threads = kGlareCpuThreads);

  // The mixture for this adaptation luminance (Spencer adaptive; otherwise fixed). Cheap when it
  // does not change.
  void adapt(double adaptation_cd_m2);
  const spencer::Mixture& mixture() const { return mixture_; }
  // The frame convolved with the current kernel (alpha copied). The kernel does not move with the
  // eye, and a dynamic interval brings one composed frame many times: a source equal bit for bit to
  // the last one, under the same kernel, gets the kept glare (a copy, no convolution).
  void convolve(const ImageRGBA& source, ImageRGBA& out);
  // sum += the frame convolved, colour channels only (the hybrid's far part added to its near
  // part). A kept frame is added from where it is kept: no frame-sized copy.
  void add_convolution(const ImageRGBA& source, ImageRGBA& sum);
  // The glare of `source` itself, kept (as convolve() keeps it) until the next source or a new
  // mixture: valid until then. `source_token`: non-zero names the source's pixels for the caller
  // (the same token, the same pixels), so that the kept glare of that token is taken without
  // comparing them; 0: compared.
  const ImageRGBA& glare(const ImageRGBA& source, std::uint64_t source_token = 0);
  // How many convolutions were computed (not kept), for tests and the bench.
  long long convolutions_computed() const { return convolutions_computed_; }
  // Hybrid: sum(w K) per channel for the current mixture (the near part's energy).
  std::array<double, 3> energy_inside_handover() const;
  // Energy of the current kernel outside the source's own pixel, largest over channels.
  double wing_fraction() const;
  // The current kernel itself (the weighted sum of the components), for tests: kept for frames
  // whose kernels take at most kKeptKernelBytes, else std::logic_error.
  static constexpr std::size_t kKeptKernelBytes = 64u << 20;
  DisplayKernel current_kernel() const;
  // "Spencer adaptive (mixture ...), kernel W x H px, built in S s, N MB of spectra".
  std::string describe() const;
  double kernel_build_s() const { return build_s_; }
  // How many of its kernels came from the cross-session cache (glare/analytic/kernel_cache.h).
  int kernels_from_cache() const { return kernels_from_cache_; }
  std::size_t memory_bytes() const;
  // The convolution in use (automatic resolved).
  AnalyticConvolution convolution() const { return full_ ? AnalyticConvolution::full : AnalyticConvolution::two_level; }
  // The two-level convolution (its FFT sizes), or nullptr on the full path.
  const TwoLevelConvolution* two_level() const { return two_level_.get(); }
  // The largest FFT a frame takes: the full path's, or the two-level path's near level.
  int fft_rows() const;
  int fft_cols() const;

 private:
  // The glare of `source`: the kept glare when `source` is the kept frame bit for bit; else
  // computed, into the kept glare (keep_repeated_frame) or into `scratch`.
  const ImageRGBA& glare_of(const ImageRGBA& source, ImageRGBA& scratch);
  void compute(const ImageRGBA& source, ImageRGBA& out);
  std::vector<double> weights_for(const spencer::Mixture& mixture) const;
  void set_convolution_weights(const std::vector<double>& weights);
  // The components' weights now: the mixture's (adaptive), or the one kernel's 1.
  std::vector<double> current_weights() const;

  AnalyticGlareOptions options_;
  bool adaptive_ = false;
  bool per_component_ = false;  // the kernels are Spencer's components (adaptive, or with flare lines)
  std::vector<int> component_index_;  // per kernel, its component (0 f0 .. 3 f3) when per_component_
  std::vector<DisplayKernel> components_;  // kept only while small enough; see constructor
  std::vector<std::array<double, 3>> inside_;  // per component, sum(w K) per channel
  std::vector<std::array<double, 3>> centre_;  // per component, K(0, 0) per channel
  std::unique_ptr<DisplayKernelConvolution> full_;  // one of the two, as options_.convolution says
  std::unique_ptr<TwoLevelConvolution> two_level_;
  spencer::Mixture mixture_;
  bool adapted_ = false;
  double build_s_ = 0.0;
  int kernels_from_cache_ = 0;
  // The last source and its glare under the current kernel (cleared when the weights change).
  ImageRGBA last_source_, last_glare_, scratch_;
  bool last_kept_ = false;
  std::uint64_t last_token_ = 0;  // the caller's token for last_source_ (0: none)
  long long convolutions_computed_ = 0;
};

}  // namespace glarelab
