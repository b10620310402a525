#include "glare/cpu_float_glare.h"

#include "glare/fftw_float_plan.h"
#include "glare/psf_scale.h"

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
    // compute_chromatic_psf's result (psf_scale.h), each channel keeping its unit sum.
    const SpectralPsfResult spectral = chromatic_->compute(psf_, geometry.pupil_diameter_mm, geometry.total_power_error());
    return resample_psf_to_display(spectral.psf, display_degrees_per_pixel_);
  }
  // The whole power error: defocus plus the observer's refraction error (spherical: the defocus
  // phase as before, bit for bit; astigmatic: glare/astigmatic_phase.h's phase).
  psf_.transform(geometry.pupil_diameter_mm, geometry.total_power_error());
  return spectral_.compute(psf_.power(), geometry.pupil_diameter_mm);
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

}  // namespace glarelab
