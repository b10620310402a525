#pragma once
// The analytic glare of a session's frames on one display (Spencer 1995 or CIE 146): the model's
// kernel on the display's pixels (display_glare_kernel.h, twice the frame so every pixel reaches
// every other) and its FFT convolution (display_kernel_convolution.h). For the hybrid eye this is
// the far field, (1 - w) K (hybrid_psf.h), and the wave-optics near part is the caller's.
//
// Spencer's adaptive regime changes the mixture with the adaptation luminance: the kernels of f0,
// f1, f2 and the halo f3 are integrated once, their spectra kept, and a new mixture is a weighted
// sum of spectra (no new integration, no new kernel FFT). A fixed regime or CIE has one kernel.
#include <array>
#include <optional>
#include <string>

#include "core/image.h"
#include "glare/analytic_psf.h"
#include "glare/display_kernel_convolution.h"
#include "glare/hybrid_psf.h"

namespace glarelab {

struct AnalyticGlareOptions {
  GlareModel model = GlareModel::spencer;  // spencer or cie
  SpencerRegime regime = SpencerRegime::adaptive;
  ObserverEye eye;
  DisplayGeometry geometry;
  int width_px = 0, height_px = 0;  // the frames
  std::optional<HandoverPixels> handover;  // set: the hybrid's far part
};

class AnalyticGlare {
 public:
  explicit AnalyticGlare(const AnalyticGlareOptions& options, int threads = kGlareCpuThreads);

  // The mixture for this adaptation luminance (Spencer adaptive; otherwise fixed). Cheap when it
  // does not change.
  void adapt(double adaptation_cd_m2);
  const spencer::Mixture& mixture() const { return mixture_; }
  // The frame convolved with the current kernel (alpha copied).
  void convolve(const ImageRGBA& source, ImageRGBA& out) { convolution_.convolve(source, out); }
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
  std::size_t memory_bytes() const { return convolution_.spectrum_bytes(); }
  int fft_rows() const { return convolution_.fft_rows(); }
  int fft_cols() const { return convolution_.fft_cols(); }

 private:
  std::vector<double> weights_for(const spencer::Mixture& mixture) const;
  // The components' weights now: the mixture's (adaptive), or the one kernel's 1.
  std::vector<double> current_weights() const;

  AnalyticGlareOptions options_;
  bool adaptive_ = false;
  std::vector<DisplayKernel> components_;  // kept only while small enough; see constructor
  std::vector<std::array<double, 3>> inside_;  // per component, sum(w K) per channel
  std::vector<std::array<double, 3>> centre_;  // per component, K(0, 0) per channel
  DisplayKernelConvolution convolution_;
  spencer::Mixture mixture_;
  bool adapted_ = false;
  double build_s_ = 0.0;
};

}  // namespace glarelab
