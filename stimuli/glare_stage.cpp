// Glare for one composed frame. The PSF and the convolution are the compute backend's
// (glare/glare_backend.h, the same code `glarelab psf` and `bench` run); this file adds what a
// session needs around them: the eyes over time, the blink hold, the static cache, the crop to the
// region light can reach, the gaze window and the skip decision.
#include "stimuli/glare_stage.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "glare/cpu/lit_regions.h"
#include "core/parallel_for.h"
#include "glare/cpu/psf.h"
#include "glare/wave/luidolt_kernel.h"
#include "glare/wave/psf_scale.h"
#include "stimuli/display_model.h"
#include "stimuli/frame_engine.h"
#include "stimuli/luminance_range.h"

namespace glarelab {
namespace {

// The eye model needs a positive field luminance; a black frame adapts it to this (scotopic floor,
// 1e-4 cd/m2, where Eq. 2 has long reached its largest pupil).
constexpr double kMinimumFieldLuminance_cd_m2 = 1e-4;

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

void check_glare_fits_display(const GlareSpec& spec, const DisplaySpec& display) {
  check_psf_fits_display(spec.grid_px, psf_degrees_per_pixel(kReferenceWavelengthNm, spec.aperture_width_mm),
                         DisplayModel(display).degrees_per_pixel_at_centre());
}

GlareStage::GlareStage(const GlareSpec& spec, const DisplaySpec& display, std::uint64_t seed,
                       GlContextFactory gl_context)
    : spec_(spec), display_(display), seed_(seed), gl_context_(std::move(gl_context)), condition_model_(spec.model) {}

void GlareStage::set_condition(GlareModel model, double gain) {
  condition_model_ = model;
  condition_gain_ = gain;
}

void GlareStage::set_refraction(std::optional<DioptricPower> residual_error) { refraction_ = residual_error; }

std::string GlareStage::refraction_backend_reason() {
  backend();
  // Every backend computes these PSFs itself (takes_chromatic_psf): the planned float32 path with
  // float32 FFTs (glare/cpu/planned_chromatic_psf.h), the float64 reference and GL with theirs.
  return std::string("PSFs with the observer's refraction: ") + std::string(spelling(backend_kind_)) +
         ", one FFT per wavelength (" + std::to_string(spec_.wavelength_samples) +
         ") with the eye's longitudinal chromatic aberration (Thibos et al. 1992)";
}

AnalyticGlare& GlareStage::analytic_for(GlareModel model, int width_px, int height_px) {
  const auto key = std::tuple{static_cast<int>(model), width_px, height_px};
  auto found = analytic_.find(key);
  if (found != analytic_.end()) return *found->second;
  AnalyticGlareOptions options;
  // The human eye's far field is CIE 146:2002 for the observer (glare/analytic/hybrid_psf.h).
  options.model = model == GlareModel::hybrid ? spec_.hybrid_far_field : model == GlareModel::human ? GlareModel::cie : model;
  options.regime = spec_.spencer_regime;
  options.eye = spec_.observer_eye;
  options.geometry = DisplayGeometry{display_.viewing_distance_mm, display_.pixel_pitch_mm};
  options.width_px = width_px;
  options.height_px = height_px;
  if (model == GlareModel::hybrid || model == GlareModel::human) options.handover = hybrid_handover();
  options.flare_lines = spec_.spencer_flare_lines && model == GlareModel::spencer;
  options.flare_seed = seed_;
  return *analytic_.emplace(key, std::make_unique<AnalyticGlare>(options)).first->second;
}

LenticularHaloGlare& GlareStage::lenticular_halo_for(int width_px, int height_px) {
  if (!lenticular_halo_ || lenticular_halo_->width_px() != width_px || lenticular_halo_->height_px() != height_px)
    lenticular_halo_ = std::make_unique<LenticularHaloGlare>(LenticularHalo(halo_gratings(spec_.eye)),
                                                             DisplayGeometry{display_.viewing_distance_mm, display_.pixel_pitch_mm},
                                                             width_px, height_px);
  return *lenticular_halo_;
}

const PixelSolidAngle& GlareStage::solid_angle_for(int width_px, int height_px) {
  if (!solid_angle_ || solid_angle_->width_px() != width_px || solid_angle_->height_px() != height_px)
    solid_angle_.emplace(DisplayGeometry{display_.viewing_distance_mm, display_.pixel_pitch_mm}, width_px, height_px);
  return *solid_angle_;
}

GlareStage::~GlareStage() = default;

GlareBackend& GlareStage::backend() {
  if (backend_) return *backend_;
  // The frame engine's one compute choice (stimuli/frame_engine.h): "auto" on the CPU takes the
  // planned float32 path (glare/cpu/float_glare.h) for the frames; the float64 backend stays the
  // reference that "cpu" asks for by name.
  GlareBackendChoice choice = engine_glare_backend(
      spec_.backend, GlareFrameLayout{psf_options(), DisplayModel(display_).degrees_per_pixel_at_centre()}, gl_context_);
  backend_ = std::move(choice.backend);
  backend_kind_ = choice.kind;
  backend_reason_ = std::move(choice.reason);
  return *backend_;
}

PsfOptions GlareStage::psf_options() const {
  PsfOptions options;
  options.grid_px = spec_.grid_px;
  options.aperture_width_mm = spec_.aperture_width_mm;
  options.supersampling = spec_.supersampling;
  options.wavelength_nm = kReferenceWavelengthNm;
  options.spectral = true;
  options.wavelength_samples = spec_.wavelength_samples;
  options.phase = PhaseForm::defocus;
  return options;
}

const std::string& GlareStage::backend_reason() {
  backend();
  return backend_reason_;
}

void GlareStage::record_measured_pupil(double time_s, double diameter_mm) {
  measured_pupils_.emplace_back(time_s, diameter_mm);
  if (dynamic_eye_) dynamic_eye_->record_measured_pupil(time_s, diameter_mm);
}

void GlareStage::set_detected_blinks(const std::vector<DetectedBlink>& blinks) {
  detected_blinks_ = blinks;
  if (!dynamic_eye_) return;
  std::vector<std::pair<double, double>> intervals;
  for (const DetectedBlink& blink : blinks) intervals.emplace_back(blink.onset_s, blink.offset_s);
  dynamic_eye_->set_recorded_blinks(std::move(intervals));
}

EyeModel& GlareStage::eye_for(GlareMode mode, double field_luminance_cd_m2) {
  EyeParameters parameters = spec_.eye;  // [glare.eye]; the mode, instant and luminance are this eye's
  parameters.initial_field_luminance_cd_m2 = std::max(field_luminance_cd_m2, kMinimumFieldLuminance_cd_m2);
  if (mode == GlareMode::dynamic) {
    parameters.mode = GlareMode::dynamic;
    if (dynamic_start_cd_m2_)
      parameters.initial_field_luminance_cd_m2 = std::max(*dynamic_start_cd_m2_, kMinimumFieldLuminance_cd_m2);
    if (!dynamic_eye_) {
      dynamic_eye_ = std::make_unique<EyeModel>(parameters, seed_);
      for (const auto& [time_s, diameter_mm] : measured_pupils_) dynamic_eye_->record_measured_pupil(time_s, diameter_mm);
      if (detected_blinks_) set_detected_blinks(std::vector<DetectedBlink>(*detected_blinks_));
    }
    return *dynamic_eye_;
  }
  parameters.mode = GlareMode::static_eye;
  parameters.static_time_s = spec_.static_time_s;
  auto found = static_eyes_.find(parameters.initial_field_luminance_cd_m2);
  if (found == static_eyes_.end() && static_eyes_.size() >= kStaticCacheEntries) static_eyes_.clear();
  if (found == static_eyes_.end())
    found = static_eyes_.emplace(parameters.initial_field_luminance_cd_m2, std::make_unique<EyeModel>(parameters, seed_)).first;
  return *found->second;
}

void GlareStage::set_dynamic_eye_start(double field_luminance_cd_m2) {
  if (dynamic_eye_) throw std::logic_error("glare stage: the dynamic eye's start is set before its first frame");
  if (!std::isfinite(field_luminance_cd_m2) || field_luminance_cd_m2 < 0.0)
    throw std::invalid_argument("glare stage: the dynamic eye's start needs a finite luminance >= 0 cd/m2");
  dynamic_start_cd_m2_ = field_luminance_cd_m2;
}

void GlareStage::record_dynamic_frame(double time_s, double field_luminance_cd_m2) {
  record_dynamic_luminance(time_s, field_luminance_cd_m2);
  if (passed_dynamic_frames_.empty() || time_s > passed_dynamic_frames_.back().first)
    passed_dynamic_frames_.emplace_back(time_s, field_luminance_cd_m2);
}

void GlareStage::record_dynamic_luminance(double time_s, double field_luminance_cd_m2) {
  EyeModel& eye = eye_for(GlareMode::dynamic, field_luminance_cd_m2);
  if (time_s > last_recorded_s_) {
    eye.record_frame_luminance(time_s, std::max(field_luminance_cd_m2, 0.0));
    last_recorded_s_ = time_s;
  }
}

std::optional<Psf> GlareStage::display_psf(GlareMode mode, double time_s, double field_luminance_cd_m2, EyeState* state) {
  if (mode == GlareMode::control) throw std::invalid_argument("glare stage: control has no PSF");
  EyeModel& eye = eye_for(mode, field_luminance_cd_m2);
  if (mode == GlareMode::dynamic) record_dynamic_luminance(time_s, field_luminance_cd_m2);
  if (state != nullptr) *state = eye.state_at(time_s);
  PsfOptions options = psf_options();
  ApertureGeometry geometry = eye.geometry_at(time_s);
  if (refraction_) {
    geometry.refraction_error = *refraction_;
    options.observer_refraction = true;
  }
  try {
    return backend().display_psf(geometry, options, DisplayModel(display_).degrees_per_pixel_at_centre());
  } catch (const ClosedApertureError&) {
    return std::nullopt;  // the lids cover the whole pupil: no light, no PSF
  }
}

// Convolves only the parts of the frame that glare can change: the boxes around its lit pixels
// (glare/cpu/lit_regions.h), split where at least the PSF's size of black runs between them, so that
// one box's glare cannot reach another's. Outside the boxes grown by the PSF's reach the exact
// result is 0 (no light within reach), which is what the frame already holds; inside each, the
// zero-padded FFT convolution of the box alone equals that of the whole frame, because everything
// else within reach is black. A stimulus on a black background (the demo: two 256 px scenes on a
// 1024 x 512 display) costs two small convolutions.
ImageRGBA GlareStage::convolve_frame(const ImageRGBA& frame, const Psf& display_psf, std::vector<PixelRect>* changed,
                                     FrameFacts* facts) {
  std::vector<PixelRect> found;
  if (facts == nullptr) found = lit_regions(frame, display_psf.size_px);
  else if (!facts->lit_boxes.contains(display_psf.size_px))
    facts->lit_boxes.emplace(display_psf.size_px, lit_regions(frame, display_psf.size_px));
  const std::vector<PixelRect>& boxes = facts == nullptr ? found : facts->lit_boxes.at(display_psf.size_px);
  // Where each box's glare lands (boxes_reached: grown by the PSF's reach, clipped to the frame);
  // the planned path writes exactly there (CpuFloatConvolution::write_full), the others convolve
  // these crops (GlareBackend::convolve_regions).
  if (changed != nullptr) *changed = boxes_reached(boxes, display_psf.size_px, frame.width_px, frame.height_px);
  if (boxes.empty()) return frame;  // all black: so is its glare
  ImageRGBA out = frame;
  backend().convolve_regions(frame, boxes, display_psf, out);
  return out;
}

// The window and its apron (the PSF's reach, so the window is exact) convolved by the backend,
// then blended into the unconvolved frame: the computation of glare/cpu/gaze_window_convolution.h with
// the backend's convolution in place of the CPU one.
ImageRGBA GlareStage::convolve_gaze_window(const ImageRGBA& frame, const Psf& display_psf, const GazeWindow& window) {
  const int cx0 = std::max(0, window.x0_px - window.apron_px);
  const int cy0 = std::max(0, window.y0_px - window.apron_px);
  const int cx1 = std::min(frame.width_px, window.x0_px + window.width_px + window.apron_px);
  const int cy1 = std::min(frame.height_px, window.y0_px + window.height_px + window.apron_px);
  ImageRGBA crop(cx1 - cx0, cy1 - cy0);
  for (int y = cy0; y < cy1; ++y) std::copy_n(frame.pixel(cx0, y), 4 * crop.width_px, crop.pixel(0, y - cy0));
  const ImageRGBA glared = backend().convolve(crop, display_psf);
  ImageRGBA out = frame;
  for (int y = window.y0_px; y < window.y0_px + window.height_px; ++y)
    for (int x = window.x0_px; x < window.x0_px + window.width_px; ++x) {
      const double w = gaze_blend_weight(window, x, y);
      const float* convolved = glared.pixel(x - cx0, y - cy0);
      float* pixel = out.pixel(x, y);
      for (int c = 0; c < 3; ++c) {
        const double base = pixel[c];
        pixel[c] = static_cast<float>(base + w * (static_cast<double>(convolved[c]) - base));
      }
    }
  return out;
}

ImageRGBA GlareStage::glare_excess(const ImageRGBA& frame) const {
  // Spencer 1995, section 3.2 end: the viewer's eye already scatters what the display shows, so
  // only the light the display cannot show (above its peak) is spread.
  ImageRGBA excess = frame;
  const float peak = static_cast<float>(display_.peak_luminance_cd_m2);
  for (std::size_t i = 0; i < excess.rgba.size(); i += 4)
    for (int c = 0; c < 3; ++c) excess.rgba[i + c] = std::max(frame.rgba[i + c] - peak, 0.0f);
  return excess;
}

ImageRGBA GlareStage::with_gain(const ImageRGBA& frame, const ImageRGBA& source, ImageRGBA glared) const {
  // gain 1 and the whole frame as source: the glared frame itself, not frame + (glared - frame)
  // rounded in float.
  if (condition_gain_ == 1.0 && spec_.source != GlareSource::excess) return glared;
  ImageRGBA out = frame;
  for (std::size_t i = 0; i < out.rgba.size(); i += 4)
    for (int c = 0; c < 3; ++c) {
      const double change = static_cast<double>(glared.rgba[i + c]) - source.rgba[i + c];
      out.rgba[i + c] = static_cast<float>(std::max(0.0, frame.rgba[i + c] + condition_gain_ * change));
    }
  return out;
}

std::optional<Psf> GlareStage::wave_psf(GlareMode mode, double time_s, double mean_cd_m2, GlareFrameReport& r) {
  // Static: the frozen eye and the frame determine the PSF; computed once per field luminance.
  std::optional<Psf> psf;
  EyeState state;
  if (mode == GlareMode::static_eye) {
    const StaticPsfKey key{mean_cd_m2, refraction_.has_value(), refraction_ ? refraction_->xx() : 0.0,
                           refraction_ ? refraction_->xy() : 0.0, refraction_ ? refraction_->yy() : 0.0};
    auto cached = static_psfs_.find(key);
    if (cached == static_psfs_.end() && static_psfs_.size() >= kStaticCacheEntries) static_psfs_.clear();
    if (cached == static_psfs_.end()) cached = static_psfs_.emplace(key, display_psf(mode, time_s, mean_cd_m2)).first;
    psf = cached->second;
    state = eye_for(mode, mean_cd_m2).state_at(time_s);
  } else {
    psf = display_psf(mode, time_s, mean_cd_m2, &state);
    if (psf) {
      last_open_dynamic_psf_ = psf;
      passed_dynamic_frames_.clear();
    }
  }
  r.pupil_diameter_mm = state.pupil_diameter_mm;
  r.gratings_in_pupil = state.gratings_in_pupil;
  if (!psf) {
    r.eye_closed = true;
    if (mode == GlareMode::dynamic) {
      // Frames a preview passed by are later than any computed one: the latest open among them is
      // the frame whose PSF the session holds.
      while (!passed_dynamic_frames_.empty()) {
        const auto [passed_s, passed_cd_m2] = passed_dynamic_frames_.back();
        passed_dynamic_frames_.pop_back();
        if (std::optional<Psf> open = display_psf(mode, passed_s, passed_cd_m2)) {
          last_open_dynamic_psf_ = std::move(open);
          passed_dynamic_frames_.clear();
        }
      }
    }
    psf = mode == GlareMode::dynamic ? last_open_dynamic_psf_ : std::nullopt;
    if (!psf) r.skip_reason = "eye closed (blink): no light reaches the retina and no open frame came before";
  }
  return psf;
}

Psf GlareStage::luidolt_psf(GlareMode mode, double time_s, double mean_cd_m2, GlareFrameReport& r) {
  EyeModel& eye = eye_for(mode, mean_cd_m2);
  if (mode == GlareMode::dynamic) record_dynamic_luminance(time_s, mean_cd_m2);
  // Luidolt 2020, 5.2.1 ii: the tracked pupil is mapped onto 2-8 mm; the thesis has no lids or
  // gratings (Table 5.1), so a blink changes nothing here.
  const double pupil_mm = std::clamp(eye.state_at(time_s).pupil_diameter_mm, 2.0, 8.0);
  r.pupil_diameter_mm = pupil_mm;
  auto found = luidolt_psfs_.find(pupil_mm);
  if (found == luidolt_psfs_.end()) {
    if (luidolt_psfs_.size() >= kStaticCacheEntries) luidolt_psfs_.clear();
    LuidoltKernelOptions options;
    options.grid_px = spec_.grid_px;
    options.wavelength_count = spec_.wavelength_samples;
    LuidoltKernel kernel = luidolt_kernel(pupil_mm, seed_, options);
    Psf display = resample_psf_to_display(kernel.psf, DisplayModel(display_).degrees_per_pixel_at_centre());
    found = luidolt_psfs_.emplace(pupil_mm, std::pair{std::move(display), std::move(kernel.sampling_note)}).first;
  }
  r.sampling_note = found->second.second;
  return found->second.first;
}

namespace {

bool all_black(const ImageRGBA& image) {
  for (std::size_t i = 0; i < image.rgba.size(); i += 4)
    if (image.rgba[i] != 0.0f || image.rgba[i + 1] != 0.0f || image.rgba[i + 2] != 0.0f) return false;
  return true;
}

}  // namespace

ImageRGBA GlareStage::apply_analytic(const ImageRGBA& frame, const ImageRGBA& source, double mean_cd_m2,
                                     GlareFrameReport& r) {
  AnalyticGlare& analytic = analytic_for(condition_model_, frame.width_px, frame.height_px);
  // The adaptation luminance picks Spencer's mixture (adaptive regime): the field luminance the
  // eye sees, as for the wave-optics eye's pupil.
  analytic.adapt(mean_cd_m2);
  if (condition_model_ == GlareModel::spencer) r.spencer_mixture = analytic.mixture();
  r.wing_fraction = analytic.wing_fraction();
  // The kernel carries energy per pixel: the source's luminance to energy, the glare back.
  const PixelSolidAngle& solid_angle = solid_angle_for(source.width_px, source.height_px);
  ImageRGBA glared;
  analytic.convolve(solid_angle.to_energy(source), glared);
  solid_angle.to_luminance(glared);
  r.convolved = true;
  return with_gain(frame, source, std::move(glared));
}

ImageRGBA GlareStage::apply(const ImageRGBA& frame_cd_m2, GlareMode mode, double time_s, GlareFrameReport* report,
                            const std::optional<GazePoint>& gaze, std::optional<double> field_luminance_cd_m2,
                            FrameFacts* facts) {
  return apply_to(frame_cd_m2, mode, time_s, report, gaze, field_luminance_cd_m2, facts, nullptr);
}

GlareStage::GlaredOnGpu GlareStage::apply_on_gpu(const ImageRGBA& frame_cd_m2, GlareMode mode, double time_s,
                                                 GlareFrameReport* report, const std::optional<GazePoint>& gaze,
                                                 std::optional<double> field_luminance_cd_m2, FrameFacts* facts) {
  GlaredOnGpu glared;
  glared.image = apply_to(frame_cd_m2, mode, time_s, report, gaze, field_luminance_cd_m2, facts, &glared.gpu_buffer);
  return glared;
}

ImageRGBA GlareStage::apply_to(const ImageRGBA& frame_cd_m2, GlareMode mode, double time_s, GlareFrameReport* report,
                               const std::optional<GazePoint>& gaze, std::optional<double> field_luminance_cd_m2,
                               FrameFacts* facts, unsigned* gpu_buffer) {
  GlareFrameReport local;
  GlareFrameReport& r = report != nullptr ? *report : local;
  r = GlareFrameReport{};
  r.mode = mode;
  r.model = condition_model_;
  r.gain = condition_gain_;
  if (mode == GlareMode::control) return frame_cd_m2;

  // Not value_or(mean_luminance(...)): that would scan the frame even when the field is given.
  const double mean_cd_m2 = field_luminance_cd_m2 ? *field_luminance_cd_m2 : mean_luminance(frame_cd_m2);
  // The light the glare spreads: the frame itself (no copy), or its excess over the display's peak.
  std::optional<ImageRGBA> excess;
  if (spec_.source == GlareSource::excess) excess = glare_excess(frame_cd_m2);
  const ImageRGBA& source = excess ? *excess : frame_cd_m2;
  if (excess && all_black(source)) {
    // Nothing above the display's peak: the frame is shown as it is, bit for bit.
    if (mode == GlareMode::dynamic) record_dynamic_luminance(time_s, mean_cd_m2);
    r.skip_reason = "nothing above the display's peak of " + std::to_string(display_.peak_luminance_cd_m2) +
                    " cd/m2 (source = \"excess\")";
    return frame_cd_m2;
  }
  if (condition_gain_ == 0.0) {
    if (mode == GlareMode::dynamic) record_dynamic_luminance(time_s, mean_cd_m2);
    r.skip_reason = "glare_gain 0";
    return frame_cd_m2;
  }
  if (condition_model_ != GlareModel::ritschel && condition_model_ != GlareModel::luidolt) {
    // The analytic, hybrid and human kernels reach every pixel, so a gaze window's exact apron is the
    // whole frame: its glare is the frame's, confined by the window's blend (docs/GLARE_OPTICS.md 7a).
    const bool analytic = condition_model_ == GlareModel::spencer || condition_model_ == GlareModel::cie;
    // The hybrid and human eyes' frame may stay on the GPU (its far part and halo made on the host
    // once per composed frame): at gain 1, the frame its own source, no gaze window.
    unsigned* hybrid_on_gpu =
        !analytic && spec_.gaze_window_px == 0 && condition_gain_ == 1.0 && !excess ? gpu_buffer : nullptr;
    ImageRGBA glared = analytic ? apply_analytic(frame_cd_m2, source, mean_cd_m2, r)
                                : apply_hybrid(frame_cd_m2, source, mode, time_s, mean_cd_m2, r,
                                               excess ? nullptr : facts, hybrid_on_gpu);
    if (hybrid_on_gpu != nullptr && *hybrid_on_gpu != 0) return glared;  // empty: the frame is on the GPU
    if (spec_.gaze_window_px == 0 || !r.convolved) return glared;
    GazeWindowOptions options;
    options.window_px = spec_.gaze_window_px;
    const GazePoint at = gaze.value_or(GazePoint{});
    r.window = place_gaze_window(source.width_px, source.height_px, at.x, at.y,
                                 2 * std::max(source.width_px, source.height_px), options);
    return blend_gaze_window(frame_cd_m2, glared, *r.window);
  }

  std::optional<Psf> psf = condition_model_ == GlareModel::luidolt ? luidolt_psf(mode, time_s, mean_cd_m2, r)
                                                                    : wave_psf(mode, time_s, mean_cd_m2, r);
  if (!psf) return frame_cd_m2;
  r.wing_fraction = psf_wing_fraction(*psf);
  // One pass for both when the frame is its own source.
  if (facts != nullptr && !facts->luminance_range_cd_m2) facts->luminance_range_cd_m2 = luminance_range(frame_cd_m2);
  const auto [frame_min_cd_m2, frame_max_cd_m2] =
      facts != nullptr ? *facts->luminance_range_cd_m2 : luminance_range(frame_cd_m2);
  const double source_max_cd_m2 = excess ? luminance_range(source).second : frame_max_cd_m2;
  r.visibility_bound = condition_gain_ * visibility_bound(source_max_cd_m2, frame_min_cd_m2, r.wing_fraction,
                                                          spec_.visibility_floor_cd_m2);
  if (spec_.skip_invisible && r.visibility_bound < spec_.visibility_weber_fraction) {
    r.skip_reason = "invisible: glare changes no pixel by more than " + std::to_string(r.visibility_bound) +
                    " (relative; threshold " + std::to_string(spec_.visibility_weber_fraction) + ")";
    return frame_cd_m2;
  }
  r.convolved = true;
  if (spec_.gaze_window_px == 0) {
    // The frame as its own source at gain 1: the glared frame is convolve_frame's, so it changes
    // only where that says.
    const bool confined = condition_gain_ == 1.0 && !excess;
    if (gpu_buffer != nullptr && confined) {
      // The whole frame convolved where the backend keeps it on the GPU (no lit boxes: they would
      // be cut out of the frame on the host; outside them the whole frame's glare is 0 plus the
      // FFT's rounding, 1e-7 of the dim part's energy, the bright pixels being summed directly).
      *gpu_buffer = backend().convolve_on_gpu(source, *psf, facts != nullptr ? facts->gpu_scene_token : 0);
      if (*gpu_buffer != 0) return {};
    }
    std::vector<PixelRect> changed;
    // The frame's facts hold for the source only when the source is the frame.
    ImageRGBA glared = convolve_frame(source, *psf, confined ? &changed : nullptr, excess ? nullptr : facts);
    if (confined) r.changed_boxes = std::move(changed);
    return with_gain(frame_cd_m2, source, std::move(glared));
  }
  GazeWindowOptions options;
  options.window_px = spec_.gaze_window_px;
  const GazePoint at = gaze.value_or(GazePoint{});
  r.window = place_gaze_window(source.width_px, source.height_px, at.x, at.y, psf->size_px, options);
  return with_gain(frame_cd_m2, source, convolve_gaze_window(source, *psf, *r.window));
}

}  // namespace glarelab
