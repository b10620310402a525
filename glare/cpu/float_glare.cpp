#include "glare/cpu/float_glare.h"

#include <algorithm>
#include <cstring>

#include "glare/cpu/fftw_float_plan.h"
#include "glare/wave/psf_scale.h"

namespace glarelab {
namespace {

CpuFloatPsfSettings psf_settings(const CpuFloatGlareSettings& settings) {
  CpuFloatPsfSettings psf;
  psf.raster.grid_px = settings.grid_px;
  psf.raster.aperture_width_mm = settings.aperture_width_mm;
  psf.raster.supersampling = settings.supersampling;
  psf.wavelength_nm = settings.reference_wavelength_nm;
  psf.phase = PhaseForm::defocus;
  return psf;
}

CpuFloatSpectralSettings spectral_settings(const CpuFloatGlareSettings& settings, double psf_degrees_per_pixel) {
  CpuFloatSpectralSettings spectral;
  spectral.grid_px = settings.grid_px;
  spectral.psf_degrees_per_pixel = psf_degrees_per_pixel;
  spectral.display_degrees_per_pixel = settings.display_degrees_per_pixel;
  spectral.wavelength_samples = settings.wavelength_samples;
  spectral.reference_wavelength_nm = settings.reference_wavelength_nm;
  spectral.aperture_width_mm = settings.aperture_width_mm;
  spectral.threads = kGlareCpuThreads;
  return spectral;
}

}  // namespace

CpuFloatGlare::CpuFloatGlare(const CpuFloatGlareSettings& settings)
    : psf_(psf_settings(settings)),
      spectral_(spectral_settings(settings, psf_.degrees_per_pixel())),
      display_degrees_per_pixel_(settings.display_degrees_per_pixel) {
  if (settings.longitudinal_chromatic_aberration) {
    CpuFloatChromaticSettings chromatic;
    chromatic.grid_px = settings.grid_px;
    chromatic.aperture_width_mm = settings.aperture_width_mm;
    chromatic.reference_wavelength_nm = settings.reference_wavelength_nm;
    chromatic.wavelength_samples = settings.wavelength_samples;
    chromatic_ = std::make_unique<CpuFloatChromaticPsf>(chromatic);
  }
}

Psf CpuFloatGlare::display_psf(const ApertureGeometry& geometry) {
  psf_.rasterise(geometry);
  if (chromatic_) {
    // One FFT per wavelength on the N x N grid, then the box resampling the float64 path applies to
    // compute_chromatic_psf's result (glare/wave/psf_scale.h), each channel keeping its unit sum.
    const SpectralPsfResult spectral = chromatic_->compute(psf_, geometry.pupil_diameter_mm, geometry.total_power_error());
    return resample_psf_to_display(spectral.psf, display_degrees_per_pixel_);
  }
  // The whole power error: defocus plus the observer's refraction error (spherical: the defocus
  // phase as before, bit for bit; astigmatic: glare/refraction/astigmatic_phase.h's phase).
  psf_.transform(geometry.pupil_diameter_mm, geometry.total_power_error());
  return spectral_.compute(psf_.power_column_major(), geometry.pupil_diameter_mm);
}

ImageRGBA CpuFloatGlare::convolve(const ImageRGBA& image, const Psf& display_psf) {
  if (!convolution_ || convolution_width_px_ != image.width_px || convolution_height_px_ != image.height_px ||
      convolution_kernel_px_ != display_psf.size_px) {
    convolution_ = std::make_unique<CpuFloatConvolution>(image.width_px, image.height_px, display_psf.size_px);
    convolution_width_px_ = image.width_px;
    convolution_height_px_ = image.height_px;
    convolution_kernel_px_ = display_psf.size_px;
    scene_ = ImageRGBA();
  }
  reused_scene_ = scene_.width_px == image.width_px && scene_.height_px == image.height_px && scene_.rgba == image.rgba &&
                  scene_.depth == image.depth;
  if (!reused_scene_) {
    convolution_->set_scene(image);
    scene_ = image;
  }
  ImageRGBA out;
  convolution_->convolve(display_psf, out);
  return out;
}

namespace {

// Whether `pixels` holds the RGBA rows of `box` in `frame`, bit for bit.
bool same_pixels(const std::vector<float>& pixels, const ImageRGBA& frame, const PixelBox& box) {
  const std::size_t row_floats = 4 * static_cast<std::size_t>(box.width);
  if (pixels.size() != row_floats * box.height) return false;
  for (int y = 0; y < box.height; ++y)
    if (std::memcmp(pixels.data() + row_floats * y, frame.pixel(box.x0, box.y0 + y), row_floats * sizeof(float)) != 0)
      return false;
  return true;
}

void keep_pixels(std::vector<float>& pixels, const ImageRGBA& frame, const PixelBox& box) {
  const std::size_t row_floats = 4 * static_cast<std::size_t>(box.width);
  pixels.resize(row_floats * box.height);
  for (int y = 0; y < box.height; ++y) std::copy_n(frame.pixel(box.x0, box.y0 + y), row_floats, pixels.data() + row_floats * y);
}

// Plans kept for this many box sizes at most (a session shows few layouts; past it they are made again).
constexpr std::size_t kRegionPlans = 8;

}  // namespace

void CpuFloatGlare::convolve_regions(const ImageRGBA& frame, const std::vector<PixelBox>& boxes, const Psf& display_psf,
                                     ImageRGBA& out) {
  if (out.width_px != frame.width_px || out.height_px != frame.height_px)
    throw std::invalid_argument("glare/cpu/float_glare: the output is not the frame's size");
  if (region_kernel_px_ != display_psf.size_px) {
    region_plans_.clear();
    region_kernel_px_ = display_psf.size_px;
  }
  // The boxes of each size, in list order: their slots.
  std::map<std::pair<int, int>, std::vector<const PixelBox*>> by_size;
  for (const PixelBox& box : boxes) {
    if (box.width <= 0 || box.height <= 0 || box.x0 < 0 || box.y0 < 0 || box.x0 + box.width > frame.width_px ||
        box.y0 + box.height > frame.height_px)
      throw std::invalid_argument("glare/cpu/float_glare: a region does not lie inside the frame");
    by_size[{box.width, box.height}].push_back(&box);
  }
  reused_scene_ = true;
  for (const auto& [size, sized] : by_size) {
    auto found = region_plans_.find(size);
    const int slots = static_cast<int>(sized.size());
    if (found == region_plans_.end() || found->second.convolution->slots() < slots) {
      if (found == region_plans_.end() && region_plans_.size() >= kRegionPlans) region_plans_.clear();
      RegionPlan plan;
      plan.convolution = std::make_unique<CpuFloatConvolution>(size.first, size.second, display_psf.size_px,
                                                                kGlareCpuThreads, ConvolutionOutput::full, slots);
      plan.pixels.resize(static_cast<std::size_t>(slots));
      found = region_plans_.insert_or_assign(size, std::move(plan)).first;
    }
    RegionPlan& plan = found->second;
    for (int slot = 0; slot < slots; ++slot) {
      const PixelBox& box = *sized[static_cast<std::size_t>(slot)];
      std::vector<float>& kept = plan.pixels[static_cast<std::size_t>(slot)];
      if (same_pixels(kept, frame, box)) continue;
      reused_scene_ = false;
      kept.clear();  // a refused scene leaves no stale match behind
      plan.convolution->set_scene(frame, box.x0, box.y0, slot);
      keep_pixels(kept, frame, box);
    }
    plan.convolution->set_kernel(display_psf);
    for (int slot = 0; slot < slots; ++slot) {
      const PixelBox& box = *sized[static_cast<std::size_t>(slot)];
      plan.convolution->write_full(slot, out, box.x0, box.y0);
    }
  }
}

}  // namespace glarelab
