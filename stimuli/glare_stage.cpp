// Glare for one composed frame, on the CPU (glare/psf_cpu, spectral_psf, psf_scale, convolution_cpu).
// The whole CPU path sits in GlareStage::display_psf() and convolve_frame(): replacing them with a
// compute backend is a change to those two functions only.
#include "stimuli/glare_stage.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "glare/aperture_raster.h"
#include "glare/convolution_cpu.h"
#include "glare/psf_cpu.h"
#include "glare/psf_scale.h"
#include "glare/spectral_psf.h"
#include "stimuli/display_model.h"

namespace glarelab {
namespace {

// The eye model needs a positive field luminance; a black frame adapts it to this (scotopic floor,
// 1e-4 cd/m2, where Eq. 2 has long reached its largest pupil).
constexpr double kMinimumFieldLuminance_cd_m2 = 1e-4;

double min_luminance(const ImageRGBA& image) {
  double lowest = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i + 3 < image.rgba.size(); i += 4)
    lowest = std::min(lowest, luminance_rec709(image.rgba[i], image.rgba[i + 1], image.rgba[i + 2]));
  return image.empty() ? 0.0 : lowest;
}

// Convolves only the part of the frame that glare can change: the bounding box of its non-black
// pixels grown by the PSF's half-size. Outside it the exact result is 0 (no light within the PSF's
// reach), which is what the frame already holds; inside it the zero-padded FFT convolution of the
// crop equals that of the whole frame, because everything the crop leaves out is black. A stimulus
// on a black background (the demo: two 256 px scenes on a 1024 x 512 display) costs a fraction.
ImageRGBA convolve_frame(const ImageRGBA& frame, const Psf& display_psf) {
  ConvolutionOptions options;
  options.precision = FftPrecision::float64;
  int x0 = frame.width_px, y0 = frame.height_px, x1 = -1, y1 = -1;
  for (int y = 0; y < frame.height_px; ++y)
    for (int x = 0; x < frame.width_px; ++x) {
      const float* p = frame.pixel(x, y);
      if (p[0] != 0.0f || p[1] != 0.0f || p[2] != 0.0f) {
        x0 = std::min(x0, x), x1 = std::max(x1, x), y0 = std::min(y0, y), y1 = std::max(y1, y);
      }
    }
  if (x1 < 0) return frame;  // all black: so is its glare
  const int reach = display_psf.size_px / 2;
  x0 = std::max(0, x0 - reach), y0 = std::max(0, y0 - reach);
  x1 = std::min(frame.width_px - 1, x1 + reach), y1 = std::min(frame.height_px - 1, y1 + reach);
  if (x0 == 0 && y0 == 0 && x1 == frame.width_px - 1 && y1 == frame.height_px - 1 && frame.depth.empty())
    return convolve_image_cpu(frame, display_psf, options);
  ImageRGBA crop(x1 - x0 + 1, y1 - y0 + 1);
  for (int y = y0; y <= y1; ++y) std::copy_n(frame.pixel(x0, y), 4 * crop.width_px, crop.pixel(0, y - y0));
  const ImageRGBA glared = convolve_image_cpu(crop, display_psf, options);
  ImageRGBA out = frame;
  for (int y = y0; y <= y1; ++y) std::copy_n(glared.pixel(0, y - y0), 4 * crop.width_px, out.pixel(x0, y));
  return out;
}

}  // namespace

double psf_wing_fraction(const Psf& display_psf) {
  const int n = display_psf.size_px;
  double wing = 0.0;
  for (int c = 0; c < display_psf.channels; ++c) {
    double total = 0.0;
    for (std::size_t i = 0; i < static_cast<std::size_t>(n) * n; ++i)
      total += display_psf.values[static_cast<std::size_t>(c) * n * n + i];
    if (total > 0.0) wing = std::max(wing, 1.0 - display_psf.at(c, n / 2, n / 2) / total);
  }
  return wing;
}

double visibility_bound(double peak_cd_m2, double min_cd_m2, double wing_fraction, double floor_cd_m2) {
  return peak_cd_m2 * wing_fraction / std::max(min_cd_m2, floor_cd_m2);
}

GlareStage::GlareStage(const GlareSpec& spec, const DisplaySpec& display, std::uint64_t seed)
    : spec_(spec), display_(display), seed_(seed) {}

GlareStage::~GlareStage() = default;

EyeModel& GlareStage::eye_for(GlareMode mode, double field_luminance_cd_m2) {
  EyeParameters parameters;
  parameters.initial_field_luminance_cd_m2 = std::max(field_luminance_cd_m2, kMinimumFieldLuminance_cd_m2);
  if (mode == GlareMode::dynamic) {
    parameters.mode = GlareMode::dynamic;
    if (!dynamic_eye_) dynamic_eye_ = std::make_unique<EyeModel>(parameters, seed_);
    return *dynamic_eye_;
  }
  parameters.mode = GlareMode::static_eye;
  parameters.static_time_s = spec_.static_time_s;
  auto found = static_eyes_.find(parameters.initial_field_luminance_cd_m2);
  if (found == static_eyes_.end())
    found = static_eyes_.emplace(parameters.initial_field_luminance_cd_m2, std::make_unique<EyeModel>(parameters, seed_)).first;
  return *found->second;
}

std::optional<Psf> GlareStage::display_psf(GlareMode mode, double time_s, double field_luminance_cd_m2, EyeState* state) {
  if (mode == GlareMode::control) throw std::invalid_argument("glare stage: control has no PSF");
  EyeModel& eye = eye_for(mode, field_luminance_cd_m2);
  if (mode == GlareMode::dynamic && time_s > last_recorded_s_) {
    eye.record_frame_luminance(time_s, std::max(field_luminance_cd_m2, 0.0));
    last_recorded_s_ = time_s;
  }
  if (state != nullptr) *state = eye.state_at(time_s);
  const ApertureGeometry geometry = eye.geometry_at(time_s);
  MonochromaticPsfOptions options;
  options.raster.grid_px = spec_.grid_px;
  options.raster.aperture_width_mm = spec_.aperture_width_mm;
  options.raster.supersampling = spec_.supersampling;
  options.wavelength_nm = 575.0;  // Ritschel's reference wavelength (section 5)
  options.phase = PhaseForm::defocus;
  const ApertureGrid aperture = rasterise_aperture(geometry, options.raster);
  if (std::all_of(aperture.transmittance.begin(), aperture.transmittance.end(), [](double a) { return a == 0.0; }))
    return std::nullopt;
  const MonochromaticPsfResult mono =
      compute_monochromatic_psf(aperture, geometry.pupil_diameter_mm, geometry.defocus_dioptres, options);
  SpectralPsfOptions spectral;
  spectral.wavelength_samples = spec_.wavelength_samples;
  spectral.reference_wavelength_nm = options.wavelength_nm;
  const SpectralPsfResult colour = spectral_psf_from_reference(mono.psf, spectral);
  return resample_psf_to_display(colour.psf, DisplayModel(display_).degrees_per_pixel_at_centre());
}

ImageRGBA GlareStage::apply(const ImageRGBA& frame_cd_m2, GlareMode mode, double time_s, GlareFrameReport* report) {
  GlareFrameReport local;
  GlareFrameReport& r = report != nullptr ? *report : local;
  r = GlareFrameReport{};
  r.mode = mode;
  if (mode == GlareMode::control) return frame_cd_m2;

  const double mean_cd_m2 = mean_luminance(frame_cd_m2);
  // Static: the frozen eye and the frame determine the PSF; computed once per field luminance.
  std::optional<Psf> psf;
  EyeState state;
  if (mode == GlareMode::static_eye) {
    auto cached = static_psfs_.find(mean_cd_m2);
    if (cached == static_psfs_.end()) cached = static_psfs_.emplace(mean_cd_m2, display_psf(mode, time_s, mean_cd_m2)).first;
    psf = cached->second;
    state = eye_for(mode, mean_cd_m2).state_at(time_s);
  } else {
    psf = display_psf(mode, time_s, mean_cd_m2, &state);
    if (psf) last_open_dynamic_psf_ = psf;
  }
  r.pupil_diameter_mm = state.pupil_diameter_mm;
  r.gratings_in_pupil = state.gratings_in_pupil;
  if (!psf) {
    r.eye_closed = true;
    psf = mode == GlareMode::dynamic ? last_open_dynamic_psf_ : std::nullopt;
    if (!psf) {
      r.skip_reason = "eye closed (blink): no light reaches the retina and no open frame came before";
      return frame_cd_m2;
    }
  }
  r.wing_fraction = psf_wing_fraction(*psf);
  r.visibility_bound =
      visibility_bound(max_luminance(frame_cd_m2), min_luminance(frame_cd_m2), r.wing_fraction, spec_.visibility_floor_cd_m2);
  if (spec_.skip_invisible && r.visibility_bound < spec_.visibility_weber_fraction) {
    r.skip_reason = "invisible: glare changes no pixel by more than " + std::to_string(r.visibility_bound) +
                    " (relative; threshold " + std::to_string(spec_.visibility_weber_fraction) + ")";
    return frame_cd_m2;
  }
  r.convolved = true;
  return convolve_frame(frame_cd_m2, *psf);
}

}  // namespace glarelab
