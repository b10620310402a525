#include "stimuli/perception/acuity_loss.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <stdexcept>
#include <string>

#include "stimuli/display_model.h"
#include "stimuli/perception/lab_colour.h"

namespace glarelab {
namespace {

// 1.86 sqrt(2), the denominator of Eq. 5.15 besides fov and R.
const double kKrawczykFactor = 1.86 * std::sqrt(2.0);

std::size_t at(int x, int y, int width) { return static_cast<std::size_t>(y) * width + x; }

// max_sigma_px <= 10 (validate_acuity_settings): radius <= 30.
constexpr int kMaxKernelSize = 61;

// The normalised sampled Gaussian of acuity_kernel into weights[0 .. 2 radius]; returns the radius.
int fill_kernel(double sigma_px, double* weights) {
  const int radius = acuity_kernel_radius_px(sigma_px);
  if (radius == 0) {
    weights[0] = 1.0;
    return 0;
  }
  double sum = 0.0;
  for (int k = -radius; k <= radius; ++k) {
    const double w = std::exp(-static_cast<double>(k * k) / (2.0 * sigma_px * sigma_px));
    weights[k + radius] = w;
    sum += w;
  }
  for (int k = 0; k <= 2 * radius; ++k) weights[k] /= sum;
  return radius;
}

// One 1D pass along x (dx = 1) or y (dx = 0): each output pixel uses the kernel of sigma_px[i].
std::vector<double> blur_pass(const std::vector<double>& plane, const std::vector<double>& sigma_px, int width,
                              int height, bool horizontal) {
  std::vector<double> out(plane.size());
  // Neighbouring pixels often share a sigma (0, or the cap): their kernel is made once.
  double kernel[kMaxKernelSize];
  double kernel_sigma = -1.0;
  int radius = 0;
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      const std::size_t i = at(x, y, width);
      if (sigma_px[i] == 0.0) {  // the kernel {1}
        out[i] = plane[i];
        continue;
      }
      if (sigma_px[i] != kernel_sigma) {
        radius = fill_kernel(sigma_px[i], kernel);
        kernel_sigma = sigma_px[i];
      }
      double sum = 0.0;
      for (int k = -radius; k <= radius; ++k) {
        const int sx = horizontal ? std::clamp(x + k, 0, width - 1) : x;
        const int sy = horizontal ? y : std::clamp(y + k, 0, height - 1);
        sum += kernel[k + radius] * plane[at(sx, sy, width)];
      }
      out[i] = sum;
    }
  return out;
}

std::vector<double> sigma_map(const std::vector<double>& lightness, const AcuitySettings& settings,
                              double pixels_per_degree) {
  std::vector<double> sigma(lightness.size());
  for (std::size_t i = 0; i < lightness.size(); ++i)
    sigma[i] = acuity_sigma_px(lightness[i], settings, pixels_per_degree);
  return sigma;
}

void check_inputs(const std::vector<double>& lightness, int width, int height, const AcuitySettings& settings,
                  double pixels_per_degree) {
  if (width <= 0 || height <= 0 || lightness.size() != static_cast<std::size_t>(width) * height)
    throw std::invalid_argument("perception acuity: the lightness plane does not match its size");
  validate_acuity_settings(settings);
  if (!std::isfinite(pixels_per_degree) || pixels_per_degree <= 0.0)
    throw std::invalid_argument("perception acuity: pixels per degree must be finite and > 0 (got " +
                                std::to_string(pixels_per_degree) + ")");
}

template <typename Blur>
ImageRGBA apply_on_lightness(const ImageRGBA& frame, const AcuitySettings& settings, double pixels_per_degree,
                             Blur blur) {
  if (frame.empty()) throw std::invalid_argument("perception acuity: the frame is empty");
  const int width = frame.width_px, height = frame.height_px;
  const std::size_t n = static_cast<std::size_t>(width) * height;
  std::vector<LabColour> lab(n);
  std::vector<double> lightness(n);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      const float* p = frame.pixel(x, y);
      const std::size_t i = at(x, y, width);
      lab[i] = rec709_to_lab(p[0], p[1], p[2], settings.reference_white_cd_m2);
      lightness[i] = lab[i].lightness;
    }
  const std::vector<double> blurred = blur(lightness, width, height, settings, pixels_per_degree);
  ImageRGBA out = frame;
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      const std::size_t i = at(x, y, width);
      if (blurred[i] == lightness[i]) continue;  // untouched pixels keep their exact input values
      LabColour changed = lab[i];
      changed.lightness = blurred[i];
      double rgb[3];
      lab_to_rec709(changed, settings.reference_white_cd_m2, rgb);
      float* q = out.pixel(x, y);
      for (int c = 0; c < 3; ++c) q[c] = static_cast<float>(rgb[c]);
    }
  return out;
}

}  // namespace

void validate_acuity_settings(const AcuitySettings& settings) {
  if (!std::isfinite(settings.reference_white_cd_m2) || settings.reference_white_cd_m2 <= 0.0)
    throw std::invalid_argument("perception acuity: reference_white_cd_m2 must be finite and > 0 (got " +
                                std::to_string(settings.reference_white_cd_m2) + ")");
  if (!std::isfinite(settings.max_sigma_px) || settings.max_sigma_px <= 0.0 || settings.max_sigma_px > 10.0)
    throw std::invalid_argument("perception acuity: max_sigma_px must be in (0, 10] (got " +
                                std::to_string(settings.max_sigma_px) + ")");
}

double larson_resolvable_frequency_cpd(double luminance_cd_m2) {
  return 17.25 * std::atan(1.4 * std::log10(luminance_cd_m2) + 0.35) + 25.72;  // Eq. 5.14
}

double display_pixels_per_degree(const DisplaySpec& display) {
  return 1.0 / DisplayModel(display).degrees_per_pixel_at_centre();
}

double acuity_sigma_px(double lightness, const AcuitySettings& settings, double pixels_per_degree) {
  if (!(lightness < 1.0)) return 0.0;  // Eq. 5.16's support: no blur where L* >= 1
  double sigma = 0.0;
  if (settings.sigma_form == AcuitySigmaForm::luidolt_linear) {
    sigma = std::max(1.0 - lightness, 0.0);  // Eq. 5.16
  } else {
    const double luminance = luminance_of_lab_lightness(std::max(lightness, 0.0), settings.reference_white_cd_m2);
    const double resolvable_cpd = larson_resolvable_frequency_cpd(luminance);
    // Eq. 5.15; where R <= 0 (Y <= 6.5e-10 cd/m2) nothing is resolvable and the cap applies.
    sigma = resolvable_cpd > 0.0 ? pixels_per_degree / (kKrawczykFactor * resolvable_cpd) : settings.max_sigma_px;
  }
  return std::min(sigma, settings.max_sigma_px);
}

int acuity_kernel_radius_px(double sigma_px) { return static_cast<int>(std::floor(3.0 * sigma_px)); }

std::vector<double> acuity_kernel(double sigma_px) {
  if (!std::isfinite(sigma_px) || sigma_px < 0.0 || acuity_kernel_radius_px(sigma_px) >= kMaxKernelSize / 2 + 1)
    throw std::invalid_argument("perception acuity: a kernel sigma must be in [0, 10] pixels (got " +
                                std::to_string(sigma_px) + ")");
  double weights[kMaxKernelSize];
  const int radius = fill_kernel(sigma_px, weights);
  return std::vector<double>(weights, weights + 2 * radius + 1);
}

std::vector<double> blur_lightness_separable(const std::vector<double>& lightness, int width_px, int height_px,
                                             const AcuitySettings& settings, double pixels_per_degree) {
  check_inputs(lightness, width_px, height_px, settings, pixels_per_degree);
  const std::vector<double> first_sigma = sigma_map(lightness, settings, pixels_per_degree);
  const std::vector<double> horizontal = blur_pass(lightness, first_sigma, width_px, height_px, true);
  const std::vector<double> second_sigma = settings.second_pass == SecondPassSigma::filtered_lightness
                                               ? sigma_map(horizontal, settings, pixels_per_degree)
                                               : first_sigma;
  return blur_pass(horizontal, second_sigma, width_px, height_px, false);
}

std::vector<double> blur_lightness_2d(const std::vector<double>& lightness, int width_px, int height_px,
                                      const AcuitySettings& settings, double pixels_per_degree) {
  check_inputs(lightness, width_px, height_px, settings, pixels_per_degree);
  std::vector<double> out(lightness.size());
  double kernel[kMaxKernelSize];
  double kernel_sigma = -1.0;
  int radius = 0;
  for (int y = 0; y < height_px; ++y)
    for (int x = 0; x < width_px; ++x) {
      const std::size_t i = at(x, y, width_px);
      // The 2D Gaussian of this pixel's sigma, normalised: the outer product of the normalised 1D
      // kernels (both sum to 1, so their product does).
      const double sigma = acuity_sigma_px(lightness[i], settings, pixels_per_degree);
      if (sigma != kernel_sigma) {
        radius = fill_kernel(sigma, kernel);
        kernel_sigma = sigma;
      }
      double sum = 0.0;
      for (int ky = -radius; ky <= radius; ++ky)
        for (int kx = -radius; kx <= radius; ++kx) {
          const int sx = std::clamp(x + kx, 0, width_px - 1), sy = std::clamp(y + ky, 0, height_px - 1);
          sum += kernel[ky + radius] * kernel[kx + radius] * lightness[at(sx, sy, width_px)];
        }
      out[i] = sum;
    }
  return out;
}

ImageRGBA apply_acuity_loss(const ImageRGBA& frame, const AcuitySettings& settings, double pixels_per_degree) {
  return apply_on_lightness(frame, settings, pixels_per_degree, blur_lightness_separable);
}

ImageRGBA apply_acuity_loss_2d_reference(const ImageRGBA& frame, const AcuitySettings& settings,
                                         double pixels_per_degree) {
  return apply_on_lightness(frame, settings, pixels_per_degree, blur_lightness_2d);
}

}  // namespace glarelab
