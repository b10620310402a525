#include "glare/analytic/analytic_glare.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <sstream>
#include <stdexcept>

#include "core/same_pixels.h"
#include "glare/analytic/kernel_cache.h"
#include "glare/analytic/spencer_flare_lines.h"

namespace glarelab {

namespace {

// The components of a Spencer kernel: f0, f1, f2, f3 each alone.
std::vector<spencer::Mixture> spencer_components() {
  return {{1.0, 0.0, 0.0, 0.0}, {0.0, 1.0, 0.0, 0.0}, {0.0, 0.0, 1.0, 0.0}, {0.0, 0.0, 0.0, 1.0}};
}

double component_weight(const spencer::Mixture& m, int i) { return i == 0 ? m.f0 : i == 1 ? m.f1 : i == 2 ? m.f2 : m.f3; }

}  // namespace

AnalyticGlare::AnalyticGlare(const AnalyticGlareOptions& options, int threads)
    : options_(options) {
  if (options.model != GlareModel::spencer && options.model != GlareModel::cie)
    throw std::invalid_argument("glare/analytic/analytic_glare: the model must be spencer or cie");
  if (options.flare_lines && options.model != GlareModel::spencer)
    throw std::invalid_argument("glare/analytic/analytic_glare: flare lines are Spencer's (section 3.2), not the CIE's");
  // The two-level path convolves the far field at a quarter of the resolution, which would blur the
  // lines there: with lines the far field is not smooth.
  if (options.flare_lines && options.convolution == AnalyticConvolution::two_level)
    throw std::invalid_argument("glare/analytic/analytic_glare: the two-level convolution takes the far field as smooth; "
                                "with flare lines it is not (use the full convolution)");
  const bool full = options.convolution == AnalyticConvolution::full ||
                    (options.convolution == AnalyticConvolution::automatic &&
                     (options.flare_lines ||
                      static_cast<long long>(options.width_px) * options.height_px < kTwoLevelMinimumPixels));
  if (full)
    full_ = std::make_unique<DisplayKernelConvolution>(options.width_px, options.height_px, options.width_px - 1,
                                                       options.height_px - 1, threads);
  else
    two_level_ = std::make_unique<TwoLevelConvolution>(options.width_px, options.height_px, options.split, threads);
  const auto start = std::chrono::steady_clock::now();
  std::vector<AnalyticPsf> psfs;
  if (options.model == GlareModel::cie) {
    psfs.push_back(AnalyticPsf::cie(options.eye));
  } else if (options.regime == SpencerRegime::adaptive || options.flare_lines) {
    // One kernel per component: the adaptive mixture recombines them, and the lines multiply each
    // by its own set. A fixed regime keeps only the components it weighs.
    per_component_ = true;
    adaptive_ = options.regime == SpencerRegime::adaptive;
    if (!adaptive_) mixture_ = AnalyticPsf::spencer(options.regime, 0.0, options.eye).mixture();
    const std::vector<spencer::Mixture> units = spencer_components();
    for (int i = 0; i < 4; ++i)
      if (adaptive_ || component_weight(mixture_, i) != 0.0) {
        component_index_.push_back(i);
        psfs.push_back(AnalyticPsf::spencer(units[static_cast<std::size_t>(i)]));
      }
  } else {
    psfs.push_back(AnalyticPsf::spencer(options.regime, 0.0, options.eye));
    mixture_ = psfs.back().mixture();
  }
  std::vector<DisplayKernel> kernels;
  for (std::size_t j = 0; j < psfs.size(); ++j) {
    // The CIE kernel of a large display from the cross-session cache (glare/analytic/kernel_cache.h).
    KernelCacheOutcome outcome = KernelCacheOutcome::not_kept;
    DisplayKernel kernel = cached_analytic_display_kernel(psfs[j], options.geometry, options.width_px - 1,
                                                          options.height_px - 1, threads, kCachedKernelMinimumPixels, &outcome);
    if (outcome == KernelCacheOutcome::read) ++kernels_from_cache_;
    if (options.flare_lines)
      if (const std::optional<FlareLineSet> set = flare_line_set_of_component(component_index_[j]))
        apply_flare_lines(kernel, FlareLines(*set, options.flare_seed), options.geometry, threads);
    std::array<double, 3> inside{0.0, 0.0, 0.0}, centre{0.0, 0.0, 0.0};
    for (int c = 0; c < 3; ++c) centre[c] = kernel.at(kernel.channels == 3 ? c : 0, 0, 0);
    centre_.push_back(centre);
    if (options.handover) {
      inside = analytic_energy_inside(kernel, *options.handover);
      kernel = hybrid_far_kernel(kernel, *options.handover);
    }
    inside_.push_back(inside);
    kernels.push_back(std::move(kernel));
  }
  if (full_) full_->set_components(kernels);
  else two_level_->set_components(kernels);
  // The kernels themselves are kept only for small frames (tests, the profile); a full-screen set
  // would hold hundreds of MB in double that the convolution no longer needs.
  std::size_t bytes = 0;
  for (const DisplayKernel& k : kernels) bytes += k.values.size() * sizeof(double);
  if (bytes <= kKeptKernelBytes) components_ = std::move(kernels);
  if (!adaptive_) {
    set_convolution_weights(current_weights());
    adapted_ = true;
  }
  build_s_ = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

std::string to_string(AnalyticConvolution convolution) {
  switch (convolution) {
    case AnalyticConvolution::automatic: return "automatic";
    case AnalyticConvolution::full: return "full";
    case AnalyticConvolution::two_level: return "two-level";
  }
  return "unknown";
}

const ImageRGBA& AnalyticGlare::glare_of(const ImageRGBA& source, ImageRGBA& scratch) {
  if (last_kept_ && same_pixel_bits(source, last_source_)) return last_glare_;
  if (!options_.keep_repeated_frame) {
    compute(source, scratch);
    return scratch;
  }
  last_kept_ = false;  // until the new glare is in place
  last_token_ = 0;
  compute(source, last_glare_);
  last_source_ = source;
  last_kept_ = true;
  return last_glare_;
}

void AnalyticGlare::compute(const ImageRGBA& source, ImageRGBA& out) {
  if (full_) full_->convolve(source, out);
  else two_level_->convolve(source, out);
  ++convolutions_computed_;
}

const ImageRGBA& AnalyticGlare::glare(const ImageRGBA& source, std::uint64_t source_token) {
  if (last_kept_ && source_token != 0 && source_token == last_token_) return last_glare_;
  const ImageRGBA& glare = glare_of(source, scratch_);
  last_token_ = last_kept_ ? source_token : 0;
  return glare;
}

void AnalyticGlare::convolve(const ImageRGBA& source, ImageRGBA& out) {
  const ImageRGBA& glare = glare_of(source, out);
  if (&glare != &out) out = glare;
}

void AnalyticGlare::add_convolution(const ImageRGBA& source, ImageRGBA& sum) {
  if (sum.width_px != source.width_px || sum.height_px != source.height_px)
    throw std::invalid_argument("glare/analytic/analytic_glare: the sum's frame is not the source's");
  ImageRGBA scratch;
  const ImageRGBA& glare = glare_of(source, scratch);
  for (std::size_t i = 0; i < sum.rgba.size(); i += 4)
    for (int c = 0; c < 3; ++c) sum.rgba[i + c] += glare.rgba[i + c];
}

void AnalyticGlare::set_convolution_weights(const std::vector<double>& weights) {
  last_kept_ = false;
  if (full_) full_->set_weights(weights);
  else two_level_->set_weights(weights);
}

std::size_t AnalyticGlare::memory_bytes() const { return full_ ? full_->spectrum_bytes() : two_level_->spectrum_bytes(); }
int AnalyticGlare::fft_rows() const { return full_ ? full_->fft_rows() : two_level_->near_fft_rows(); }
int AnalyticGlare::fft_cols() const { return full_ ? full_->fft_cols() : two_level_->near_fft_cols(); }

std::vector<double> AnalyticGlare::weights_for(const spencer::Mixture& m) const {
  std::vector<double> weights;
  for (int i : component_index_) weights.push_back(component_weight(m, i));
  return weights;
}

std::vector<double> AnalyticGlare::current_weights() const {
  return per_component_ ? weights_for(mixture_) : std::vector<double>{1.0};
}

void AnalyticGlare::adapt(double adaptation_cd_m2) {
  if (!adaptive_) return;
  const spencer::Mixture m =
      spencer::with_age(spencer::regime_mixture(SpencerRegime::adaptive, adaptation_cd_m2), options_.eye.age_years);
  // The weights move smoothly with luminance; a change below 1e-6 in every weight is not worth a
  // recombination of the spectra (it changes no displayed value).
  if (adapted_ && std::abs(m.f0 - mixture_.f0) < 1e-6 && std::abs(m.f2 - mixture_.f2) < 1e-6 &&
      std::abs(m.f3 - mixture_.f3) < 1e-6)
    return;
  mixture_ = m;
  set_convolution_weights(weights_for(m));
  adapted_ = true;
}

std::array<double, 3> AnalyticGlare::energy_inside_handover() const {
  std::array<double, 3> sum{0.0, 0.0, 0.0};
  const std::vector<double> weights = current_weights();
  for (std::size_t i = 0; i < inside_.size(); ++i)
    for (int c = 0; c < 3; ++c) sum[c] += weights[i] * inside_[i][c];
  return sum;
}

double AnalyticGlare::wing_fraction() const {
  const std::vector<double> weights = current_weights();
  double wing = 0.0;
  for (int c = 0; c < 3; ++c) {
    double centre = 0.0;
    for (std::size_t i = 0; i < centre_.size(); ++i) centre += weights[i] * centre_[i][c];
    wing = std::max(wing, 1.0 - centre);
  }
  return wing;
}

DisplayKernel AnalyticGlare::current_kernel() const {
  if (components_.empty()) throw std::logic_error("glare/analytic/analytic_glare: the kernels of a frame this large are not kept");
  const std::vector<double> weights = current_weights();
  DisplayKernel sum;
  sum.half_width_px = components_.front().half_width_px;
  sum.half_height_px = components_.front().half_height_px;
  sum.channels = 1;
  for (const DisplayKernel& k : components_) sum.channels = std::max(sum.channels, k.channels);
  const std::size_t n = static_cast<std::size_t>(sum.width_px()) * sum.height_px();
  sum.values.assign(static_cast<std::size_t>(sum.channels) * n, 0.0);
  for (std::size_t i = 0; i < components_.size(); ++i)
    for (int c = 0; c < sum.channels; ++c) {
      const int kc = components_[i].channels == 3 ? c : 0;
      for (std::size_t j = 0; j < n; ++j) sum.values[c * n + j] += weights[i] * components_[i].values[kc * n + j];
    }
  return sum;
}

std::string AnalyticGlare::describe() const {
  std::ostringstream out;
  out.precision(3);
  out << to_string(options_.model);
  if (options_.model == GlareModel::spencer) out << " " << to_string(options_.regime);
  if (options_.flare_lines) out << " with flare lines (seed " << options_.flare_seed << ")";
  out << " (age " << options_.eye.age_years << " years";
  if (options_.model == GlareModel::cie) out << ", pigmentation " << options_.eye.pigmentation;
  out << "), kernel " << 2 * options_.width_px - 1 << " x " << 2 * options_.height_px - 1 << " px "
      << (kernels_from_cache_ > 0 ? "read from the kernel cache" : "integrated") << " in " << build_s_ << " s, FFT " << fft_cols() << " x " << fft_rows();
  if (two_level_ && two_level_->has_far_level())
    out << " near (radius " << options_.split.near_inner_px << "-" << options_.split.near_outer_px << " px) + "
        << two_level_->far_fft_cols() << " x " << two_level_->far_fft_rows() << " far at 1/" << options_.split.factor;
  out << ", "
      << static_cast<double>(memory_bytes()) / (1024.0 * 1024.0) << " MiB of spectra";
  return out.str();
}

}  // namespace glarelab
