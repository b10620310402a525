#include "glare/cpu/float_glare.h"

#include <algorithm>
#include <cstring>
#include <stdexcept>

#include "core/parallel_for.h"
#include "glare/cpu/fftw_float_plan.h"
#include "glare/wave/psf_scale.h"
#include "glare/wave/spectral_psf.h"

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
    : settings_(settings),
      psf_(psf_settings(settings)),
      display_degrees_per_pixel_(settings.display_degrees_per_pixel) {
  // The display scale's refusals now (glare/wave/psf_scale.h), not at the first frame.
  check_psf_fits_display(settings.grid_px, psf_.degrees_per_pixel(), settings.display_degrees_per_pixel);
  if (settings.longitudinal_chromatic_aberration) chromatic_psf();  // its refusals now, not at the first frame
}

CpuPlannedChromaticPsf& CpuFloatGlare::chromatic_psf() {
  if (!chromatic_) {
    CpuPlannedChromaticSettings chromatic;
    chromatic.grid_px = settings_.grid_px;
    chromatic.aperture_width_mm = settings_.aperture_width_mm;
    chromatic.reference_wavelength_nm = settings_.reference_wavelength_nm;
    chromatic.wavelength_samples = settings_.wavelength_samples;
    chromatic_ = std::make_unique<CpuPlannedChromaticPsf>(chromatic);
  }
  return *chromatic_;
}

Psf CpuFloatGlare::display_psf(const ApertureGeometry& geometry, bool chromatic) {
  psf_.rasterise(geometry);
  last_chromatic_ = chromatic;
  if (chromatic) {
    // One FFT per wavelength on the N x N grid, then the box resampling the float64 path applies to
    // compute_chromatic_psf's result (glare/wave/psf_scale.h), each channel keeping its unit sum.
    const SpectralPsfResult spectral =
        chromatic_psf().compute(psf_, geometry.pupil_diameter_mm, geometry.total_power_error());
    return resample_psf_to_display(spectral.psf, display_degrees_per_pixel_);
  }
  // The whole power error: defocus plus the observer's refraction error (spherical: the defocus
  // phase; astigmatic: glare/refraction/astigmatic_phase.h's phase).
  psf_.transform(geometry.pupil_diameter_mm, geometry.total_power_error());
  if (!spectral_) spectral_ = std::make_unique<CpuFloatSpectralPsf>(spectral_settings(settings_, psf_.degrees_per_pixel()));
  return spectral_->compute(psf_.power_column_major(), geometry.pupil_diameter_mm);
}

std::string CpuFloatGlare::last_warning() const {
  const std::string& warning = sampling_warning();
  if (warning.empty() || !last_chromatic_) return warning;
  return warning + "; " + std::to_string(chromatic_->aliased_wavelengths()) + " of " +
         std::to_string(settings_.wavelength_samples) + " wavelengths aliased";
}

void CpuFloatGlare::check_layout(const PsfOptions& options, std::optional<double> display_degrees_per_pixel) const {
  if (options.grid_px != settings_.grid_px || options.aperture_width_mm != settings_.aperture_width_mm ||
      options.supersampling != settings_.supersampling || options.wavelength_nm != settings_.reference_wavelength_nm ||
      options.phase != PhaseForm::defocus ||
      ((display_degrees_per_pixel || options.spectral) && options.wavelength_samples != settings_.wavelength_samples) ||
      (display_degrees_per_pixel && (!options.spectral || *display_degrees_per_pixel != settings_.display_degrees_per_pixel)))
    throw std::invalid_argument("glare backend cpu float32 planned: asked for another grid, aperture, wavelength, "
                                "phase or display scale than its plans were made for, or for a monochromatic PSF at "
                                "the display's scale");
}

Psf CpuFloatGlare::psf(const ApertureGeometry& geometry, const PsfOptions& options) {
  check_layout(options, std::nullopt);
  psf_.rasterise(geometry);
  last_chromatic_ = takes_chromatic_psf(geometry, options);
  // On the aperture grid (`glarelab psf`): with the observer's refraction the per-wavelength PSF, as
  // display_psf takes it before its resampling; else the float32 transform's PSF, and the spectral
  // PSF scaled from it by the reference's operator (glare/wave/spectral_psf.h), as CpuGlareBackend
  // scales its own.
  if (last_chromatic_)
    return chromatic_psf().compute(psf_, geometry.pupil_diameter_mm, geometry.total_power_error()).psf;
  psf_.transform(geometry.pupil_diameter_mm, geometry.total_power_error());
  if (!options.spectral) return psf_.monochromatic_psf();
  SpectralPsfOptions spectral;
  spectral.wavelength_samples = options.wavelength_samples;
  spectral.reference_wavelength_nm = options.wavelength_nm;
  return spectral_psf_from_reference(psf_.monochromatic_psf(), spectral).psf;
}

Psf CpuFloatGlare::display_psf(const ApertureGeometry& geometry, const PsfOptions& options,
                               double display_degrees_per_pixel) {
  check_layout(options, display_degrees_per_pixel);
  return display_psf(geometry, settings_.longitudinal_chromatic_aberration || takes_chromatic_psf(geometry, options));
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

// Whether `kept` (a box cropped from an earlier frame) holds the RGBA of `box` in `frame`, bit for bit.
bool same_pixels(const ImageRGBA& kept, const ImageRGBA& frame, const PixelRect& box) {
  if (kept.width_px != box.width_px || kept.height_px != box.height_px) return false;
  const std::size_t row_bytes = 4 * sizeof(float) * static_cast<std::size_t>(box.width_px);
  for (int y = 0; y < box.height_px; ++y)
    if (std::memcmp(kept.pixel(0, y), frame.pixel(box.x_px, box.y_px + y), row_bytes) != 0) return false;
  return true;
}

// Plans kept for this many box sizes at most (a session shows few layouts; past it they are made again).
constexpr std::size_t kRegionPlans = 8;

}  // namespace

void CpuFloatGlare::convolve_regions(const ImageRGBA& frame, const std::vector<PixelRect>& boxes, const Psf& display_psf,
                                     ImageRGBA& out) {
  regions_into(frame, boxes, display_psf, out, nullptr, 0);
}

void CpuFloatGlare::convolve_regions_finished(const ImageRGBA& frame, const std::vector<PixelRect>& boxes,
                                              const Psf& display_psf, ImageRGBA& out, const RowFinish& finish,
                                              std::uint64_t frame_token, const ImageRGBA* added_to) {
  if (added_to != nullptr && (added_to->width_px != frame.width_px || added_to->height_px != frame.height_px))
    throw std::invalid_argument("glare/cpu/float_glare: the image the glare is added to is not the frame's size");
  // A copy, as the generic pass makes it: alpha and the pixels no box's glare reaches come with it
  // in one pass (a fresh image would be zeroed, filled and then given the frame's alpha: three
  // passes where this is one); the boxes' reaches are written over, or added to, by the inverse
  // transform.
  out = added_to != nullptr ? *added_to : frame;
  regions_into(frame, boxes, display_psf, out, &finish, frame_token,
               added_to != nullptr ? FullWrite::add : FullWrite::replace);
  // Where write_full wrote: each box grown by M/2 before and M - 1 - M/2 after (boxes_reached grows
  // by M/2 after too, one pixel more for an even M, where the glare is exactly 0).
  const int m = display_psf.size_px, before = m / 2, after = m - 1 - m / 2;
  std::vector<PixelRect> reached;
  for (const PixelRect& box : boxes)
    reached.push_back(intersection(PixelRect{box.x_px - before, box.y_px - before, box.width_px + before + after,
                                             box.height_px + before + after},
                                   image_rect(frame)));
  parallel_chunks(frame.height_px, kGlareCpuThreads, [&](int first, int last) {
    std::vector<std::pair<int, int>> spans;  // the row's reached spans, left to right
    for (int y = first; y < last; ++y) {
      spans.clear();
      for (const PixelRect& area : reached)
        if (y >= area.y_px && y < area.y_px + area.height_px) spans.emplace_back(area.x_px, area.x_px + area.width_px);
      std::sort(spans.begin(), spans.end());
      int x = 0;
      spans.emplace_back(frame.width_px, frame.width_px);
      for (const auto& [from, to] : spans) {
        if (from > x) finish(y, x, from, out.pixel(x, y));
        x = std::max(x, to);
      }
    }
  });
}

void CpuFloatGlare::regions_into(const ImageRGBA& frame, const std::vector<PixelRect>& boxes, const Psf& display_psf,
                                 ImageRGBA& out, const RowFinish* finish, std::uint64_t frame_token, FullWrite write) {
  if (out.width_px != frame.width_px || out.height_px != frame.height_px)
    throw std::invalid_argument("glare/cpu/float_glare: the output is not the frame's size");
  if (region_kernel_px_ != display_psf.size_px) {
    region_plans_.clear();
    region_kernel_px_ = display_psf.size_px;
  }
  // The boxes of each size, in list order: their slots.
  std::map<std::pair<int, int>, std::vector<const PixelRect*>> by_size;
  for (const PixelRect& box : boxes) {
    if (box.empty() || !image_rect(frame).contains(box))
      throw std::invalid_argument("glare/cpu/float_glare: a region does not lie inside the frame");
    by_size[{box.width_px, box.height_px}].push_back(&box);
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
      plan.tokens.assign(static_cast<std::size_t>(slots), 0);
      found = region_plans_.insert_or_assign(size, std::move(plan)).first;
    }
    RegionPlan& plan = found->second;
    for (int slot = 0; slot < slots; ++slot) {
      const PixelRect& box = *sized[static_cast<std::size_t>(slot)];
      ImageRGBA& kept = plan.pixels[static_cast<std::size_t>(slot)];
      std::uint64_t& token = plan.tokens[static_cast<std::size_t>(slot)];
      // The same token: the caller vouches for the same pixels (and so the same box); else compared.
      if (frame_token != 0 && token == frame_token && kept.width_px == box.width_px && kept.height_px == box.height_px)
        continue;
      if (same_pixels(kept, frame, box)) {
        token = frame_token;
        continue;
      }
      reused_scene_ = false;
      kept = ImageRGBA();  // a refused scene leaves no stale match behind
      token = 0;
      plan.convolution->set_scene(frame, box.x_px, box.y_px, slot);
      kept = crop(frame, box);
      token = frame_token;
    }
    plan.convolution->set_kernel(display_psf);
    for (int slot = 0; slot < slots; ++slot) {
      const PixelRect& box = *sized[static_cast<std::size_t>(slot)];
      plan.convolution->write_full(slot, out, box.x_px, box.y_px, finish, write);
    }
  }
}

}  // namespace glarelab
