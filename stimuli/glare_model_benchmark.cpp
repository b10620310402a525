#include "core/clock.h"
#include "stimuli/glare_model_benchmark.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <iterator>
#include <memory>
#include <sstream>
#include <vector>

#include "glare/analytic/analytic_glare.h"
#include "glare/analytic/analytic_two_level_benchmark.h"
#include "glare/refraction/dioptric_power.h"
#include "glare/analytic/display_kernel_convolution.h"
#include "glare/cpu/fftw_floor.h"
#include "glare/cpu/psf.h"
#include "glare/wave/psf_scale.h"
#include "core/fft_size.h"
#include "stimuli/display_model.h"
#include "stimuli/glare_stage.h"

namespace glarelab {
namespace {

// The FFTW floor of an RGB FFT convolution of this padded size (glare/cpu/fftw_floor.h), the fastest
// of `runs`.
double fftw_floor_s(int rows, int cols, int runs) {
  FftwRgbConvolutionFloor floor(rows, cols);
  double best = 1e300;
  for (int run = 0; run < runs; ++run) best = std::min(best, floor.run_s());
  return best;
}

void errors(const ImageRGBA& fast, const ImageRGBA& exact, double& max_error, double& l2_error) {
  double peak = 0.0, diff2 = 0.0, ref2 = 0.0, worst = 0.0;
  for (std::size_t i = 0; i < exact.rgba.size(); i += 4)
    for (int c = 0; c < 3; ++c) {
      const double e = exact.rgba[i + c], d = static_cast<double>(fast.rgba[i + c]) - e;
      peak = std::max(peak, std::abs(e));
      worst = std::max(worst, std::abs(d));
      diff2 += d * d;
      ref2 += e * e;
    }
  max_error = peak > 0.0 ? worst / peak : 0.0;
  l2_error = ref2 > 0.0 ? std::sqrt(diff2 / ref2) : 0.0;
}

// The floor of a frame of an interval: the PSF's 3 forward and the 3 inverse real transforms of
// the frame padded by the display PSF (the frame's spectrum is kept), the same size and threads.
// The default eye's error: the same frame (same eye, same time) with the near part's PSF and
// convolution on the float64 reference backend; the far part is the same two-level CIE frame in
// both (its own error is the two-level rows').
void default_eye_floor_and_error(const GlareSpec& spec, const DisplaySpec& display, const ImageRGBA& frame,
                                 double field_cd_m2, const ImageRGBA& last_human, const AnalyticBenchmarkOptions& options,
                                 AnalyticBenchmarkResult& result) {
  const int psf_px = display_psf_size_px(spec.grid_px, psf_degrees_per_pixel(kReferenceWavelengthNm, spec.aperture_width_mm),
                                         DisplayModel(display).degrees_per_pixel_at_centre());
  result.stage_fft_cols = smooth_fft_size(options.width_px + psf_px - 1);
  result.stage_fft_rows = smooth_fft_size(options.height_px + psf_px - 1);
  result.stage_floor_s = fftw_floor_s(result.stage_fft_rows, result.stage_fft_cols, options.frames);
  if (options.progress) options.progress("glare stage: human dynamic frame on the float64 reference backend");
  GlareSpec reference_spec = spec;
  reference_spec.model = GlareModel::human;
  reference_spec.backend = GlareBackendRequest::cpu;
  GlareStage reference(reference_spec, display, 1);
  for (int k = 0; k <= options.frames; ++k) {
    const ImageRGBA glared = reference.apply(frame, GlareMode::dynamic, 0.5 + k / 60.0, nullptr, std::nullopt, field_cd_m2);
    if (k == options.frames) errors(last_human, glared, result.human_max_error, result.human_l2_error);
  }
}

}  // namespace

AnalyticBenchmarkResult run_analytic_benchmark(const AnalyticBenchmarkOptions& options) {
  AnalyticBenchmarkResult result;
  result.width_px = options.width_px;
  result.height_px = options.height_px;
  result.threads = kGlareCpuThreads;
  auto say = [&](const std::string& line) {
    if (options.progress) options.progress(line);
  };
  // A dim room with five lamps and a bright window (glare/analytic/analytic_two_level_benchmark.h).
  const ImageRGBA frame = analytic_benchmark_frame(options.width_px, options.height_px);
  struct Case {
    std::string label;
    GlareModel model;
    SpencerRegime regime;
    double adaptation_cd_m2;
  };
  const Case cases[] = {{"spencer mesopic", GlareModel::spencer, SpencerRegime::mesopic, 1.0},
                        {"spencer adaptive (at 1 cd/m2)", GlareModel::spencer, SpencerRegime::adaptive, 1.0},
                        {"cie", GlareModel::cie, SpencerRegime::photopic, 1.0}};
  for (const Case& c : cases) {
    say("analytic glare: " + c.label + ", integrating the kernel over " + std::to_string(options.width_px) + " x " +
        std::to_string(options.height_px) + " display pixels");
    AnalyticGlareOptions glare_options;
    glare_options.model = c.model;
    glare_options.regime = c.regime;
    glare_options.geometry = DisplayGeometry{options.viewing_distance_mm, options.pixel_pitch_mm};
    glare_options.width_px = options.width_px;
    glare_options.height_px = options.height_px;
    // These rows time the full-resolution convolution against the FFTW floor of its own transforms;
    // the two-level path has its own rows (glare/analytic/analytic_two_level_benchmark.h).
    glare_options.convolution = AnalyticConvolution::full;
    glare_options.keep_repeated_frame = false;  // every run a convolution
    AnalyticGlare glare(glare_options);
    glare.adapt(c.adaptation_cd_m2);
    AnalyticBenchmarkRow row;
    row.model = c.label;
    row.kernel_build_s = glare.kernel_build_s();
    row.memory_mib = static_cast<double>(glare.memory_bytes()) / (1024.0 * 1024.0);
    ImageRGBA fast;
    row.frame_s = 1e300;
    for (int k = 0; k < options.frames; ++k) {
      const auto start = std::chrono::steady_clock::now();
      glare.convolve(frame, fast);
      row.frame_s = std::min(row.frame_s, seconds_since(start));
    }
    row.fft_cols = glare.fft_cols();
    row.fft_rows = glare.fft_rows();
    row.floor_s = fftw_floor_s(row.fft_rows, row.fft_cols, options.frames);
    say("analytic glare: " + c.label + ", float64 reference");
    // The reference kernel is integrated again (the engine keeps only spectra at this size); the
    // engine's mixture already holds the age term.
    const AnalyticPsf psf = c.model == GlareModel::cie ? AnalyticPsf::cie(ObserverEye{}) : AnalyticPsf::spencer(glare.mixture());
    const DisplayKernel kernel = analytic_display_kernel(psf, glare_options.geometry, options.width_px - 1,
                                                         options.height_px - 1, kGlareCpuThreads);
    errors(fast, convolve_with_kernel_float64(frame, kernel), row.max_error, row.l2_error);
    result.rows.push_back(row);
  }
  // The hybrid against the plain Ritschel frame through the glare stage, dynamic eye.
  DisplaySpec display;
  display.width_px = options.width_px;
  display.height_px = options.height_px;
  display.viewing_distance_mm = options.viewing_distance_mm;
  display.pixel_pitch_mm = options.pixel_pitch_mm;
  GlareSpec spec;
  spec.grid_px = options.ritschel_grid_px;
  spec.wavelength_samples = 16;
  spec.skip_invisible = false;
  // As a session gives them (stimuli/frame_engine.h): the field luminance the eye adapts to, and
  // the composed frame's facts, kept with it for the frames of an interval.
  const double field_cd_m2 = mean_luminance(frame);
  ImageRGBA last_human;
  // The three stages' frames in turn, frame by frame, so that a change in the machine's load or in
  // the process' heap during the run reaches each model alike (the ratios are the figures read).
  const GlareModel models[] = {GlareModel::ritschel, GlareModel::hybrid, GlareModel::human};
  std::vector<std::unique_ptr<GlareStage>> stages;
  std::vector<FrameFacts> stage_facts(std::size(models));
  for (std::size_t m = 0; m < std::size(models); ++m) {
    spec.model = models[m];
    say("glare stage: " + to_string(models[m]) + " dynamic frames at " + std::to_string(options.width_px) + " x " +
        std::to_string(options.height_px));
    stages.push_back(std::make_unique<GlareStage>(spec, display, 1));
    const auto setup = std::chrono::steady_clock::now();
    // Makes the backend and, for the hybrid, the far kernel.
    stages[m]->apply(frame, GlareMode::dynamic, 0.5, nullptr, std::nullopt, field_cd_m2, &stage_facts[m]);
    if (models[m] == GlareModel::hybrid) result.hybrid_setup_s = seconds_since(setup);
    if (models[m] == GlareModel::human) result.human_setup_s = seconds_since(setup);
  }
  double fastest_s[std::size(models)];
  std::fill(std::begin(fastest_s), std::end(fastest_s), 1e300);
  for (int k = 1; k <= options.frames; ++k)
    for (std::size_t m = 0; m < std::size(models); ++m) {
      const auto start = std::chrono::steady_clock::now();
      ImageRGBA glared = stages[m]->apply(frame, GlareMode::dynamic, 0.5 + k / 60.0, nullptr, std::nullopt, field_cd_m2,
                                          &stage_facts[m]);
      fastest_s[m] = std::min(fastest_s[m], seconds_since(start));
      if (models[m] == GlareModel::human && k == options.frames) last_human = std::move(glared);
    }
  result.ritschel_frame_s = fastest_s[0];
  result.hybrid_frame_s = fastest_s[1];
  result.human_frame_s = fastest_s[2];
  {
    // Two composed frames in turn: each frame's far glare is computed, none kept.
    GlareStage& stage = *stages[2];
    ImageRGBA other = frame;
    other.rgba[0] += 1.0f;
    result.human_new_frame_s = 1e300;
    for (int k = 1; k <= options.frames; ++k) {
      const auto start = std::chrono::steady_clock::now();
      FrameFacts new_facts;  // a new composed frame comes with facts of its own
      stage.apply(k % 2 == 0 ? frame : other, GlareMode::dynamic, 0.5 + (options.frames + k) / 60.0, nullptr,
                  std::nullopt, field_cd_m2, &new_facts);
      result.human_new_frame_s = std::min(result.human_new_frame_s, seconds_since(start));
    }
  }
  stages.clear();
  default_eye_floor_and_error(spec, display, frame, field_cd_m2, last_human, options, result);
  // The observer's refraction (docs/REFRACTION.md, "In a session"): one FFT per wavelength.
  spec.model = GlareModel::ritschel;
  result.wavelength_samples = spec.wavelength_samples;
  const DioptricPower residual = DioptricPower::from_prescription(SpheroCylinder{-1.0, -1.0, 45.0});
  for (const GlareMode mode : {GlareMode::dynamic, GlareMode::static_eye}) {
    say("glare stage: ritschel " + to_string(mode) + " frames with a refraction at " + std::to_string(options.width_px) +
        " x " + std::to_string(options.height_px));
    GlareStage stage(spec, display, 1);
    stage.set_refraction(residual);
    const auto first = std::chrono::steady_clock::now();
    stage.apply(frame, mode, 0.5);
    if (mode == GlareMode::static_eye) result.refraction_static_first_s = seconds_since(first);
    double best = 1e300;
    for (int k = 1; k <= options.frames; ++k) {
      const auto start = std::chrono::steady_clock::now();
      stage.apply(frame, mode, 0.5 + k / 60.0);
      best = std::min(best, seconds_since(start));
    }
    (mode == GlareMode::dynamic ? result.refraction_dynamic_frame_s : result.refraction_static_frame_s) = best;
  }
  return result;
}

std::string format_analytic_benchmark(const AnalyticBenchmarkResult& result) {
  std::ostringstream out;
  out.precision(3);
  out << "Analytic glare over the whole display: a " << result.width_px << " x " << result.height_px
      << " HDR frame (a dim room with lamps of 2e3-2e4 cd/m2) convolved on the planned float32 path, " << result.threads
      << " threads, against the FFTW floor of the same padded size (3 forward + 3 inverse real transforms, planned, the "
         "same threads) measured in the same run. Errors against the float64 convolution with the same kernel: max "
         "|error| / the largest glared value, and relative L2. The kernel is integrated once per session.\n\n"
      << "| model | FFT size | frame ms | floor ms | ratio | max error | L2 error | kernel s | spectra MiB |\n"
      << "|---|---|---|---|---|---|---|---|---|\n";
  for (const AnalyticBenchmarkRow& row : result.rows) {
    out << "| " << row.model << " | " << row.fft_cols << " x " << row.fft_rows << " | " << row.frame_s * 1e3 << " | "
        << row.floor_s * 1e3 << " | " << (row.floor_s > 0.0 ? row.frame_s / row.floor_s : 0.0) << " | "
        << std::scientific << row.max_error << " | " << row.l2_error << std::defaultfloat << " | " << row.kernel_build_s
        << " | " << row.memory_mib << " |\n";
  }
  out << "\nHybrid eye (Ritschel near, Spencer far) against the plain Ritschel frame through the glare stage (dynamic "
         "eye, one composed frame with a new time each frame as in a dynamic interval, so the far glare is kept; the "
         "three models' frames in turn, the fastest kept): Ritschel "
      << result.ritschel_frame_s * 1e3 << " ms, hybrid " << result.hybrid_frame_s * 1e3 << " ms ("
      << (result.ritschel_frame_s > 0.0 ? result.hybrid_frame_s / result.ritschel_frame_s : 0.0)
      << "x); the hybrid's far kernel once per session: " << result.hybrid_setup_s << " s.\n";
  out << "\nThe default eye ([glare] model \"human\": the wave-optics near field calibrated ring by ring to CIE 146, "
         "the CIE far field over the whole display) through the same stage: "
      << result.human_frame_s * 1e3 << " ms per frame of a dynamic interval, one composed frame with the eye moving ("
      << (result.ritschel_frame_s > 0.0 ? result.human_frame_s / result.ritschel_frame_s : 0.0)
      << "x the plain Ritschel frame; the far glare does not move with the eye and is kept), "
      << result.human_new_frame_s * 1e3 << " ms when every frame is a new composed frame ("
      << (result.ritschel_frame_s > 0.0 ? result.human_new_frame_s / result.ritschel_frame_s : 0.0)
      << "x); its kernels once per session: " << result.human_setup_s << " s. The floor of a frame of an interval "
      << "(the PSF's 3 forward and 3 inverse real transforms of the frame padded by the display PSF, "
      << result.stage_fft_cols << " x " << result.stage_fft_rows << ", FFTW, the same threads, this run): "
      << result.stage_floor_s * 1e3 << " ms; the default eye " << result.human_frame_s / result.stage_floor_s
      << "x it, the Ritschel frame " << result.ritschel_frame_s / result.stage_floor_s
      << "x. The default eye's frame against the same frame on the float64 reference backend (near part; the "
         "far part's two-level error is in the two-level rows): max |error| / peak "
      << std::scientific << result.human_max_error << ", L2 " << result.human_l2_error << std::defaultfloat << ".\n";
  out << "\nRitschel frame with the observer's refraction (residual -1 / -1 x 45 D; the spectral PSF one FFT per "
         "wavelength, "
      << result.wavelength_samples
      << " wavelengths, with the eye's LCA, on the CPU in float64): dynamic (a PSF every frame) "
      << result.refraction_dynamic_frame_s * 1e3 << " ms per frame ("
      << (result.ritschel_frame_s > 0.0 ? result.refraction_dynamic_frame_s / result.ritschel_frame_s : 0.0)
      << "x the plain Ritschel frame); static: its first frame (PSF and convolution, once per condition) "
      << result.refraction_static_first_s * 1e3 << " ms, a later frame (the PSF kept) "
      << result.refraction_static_frame_s * 1e3 << " ms.\n";
  return out.str();
}

}  // namespace glarelab
