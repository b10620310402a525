#include "core/clock.h"
#include "stimuli/frame_engine_benchmark.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <memory>
#include <optional>
#include <stdexcept>

#include "core/fft_size.h"
#include "core/gl/read_back.h"
#include "glare/cpu/fftw_floor.h"
#include "glare/cpu/lit_regions.h"
#include "glare/cpu/psf.h"
#include "glare/refraction/dioptric_power.h"
#include "glare/wave/psf_scale.h"
#include "stimuli/display_model.h"
#include "stimuli/frame_engine.h"
#include "stimuli/perception/stage_timing.h"

namespace glarelab {
namespace {

GlareSpec bench_glare(GlareBackendRequest backend, GlareModel model = GlareModel::ritschel) {
  GlareSpec spec;
  spec.model = model;  // by default the wave-optics eye alone: the glare these rows describe
  spec.grid_px = 256;
  spec.wavelength_samples = 16;
  spec.skip_invisible = false;
  spec.backend = backend;
  return spec;
}

// The padded sizes of the glare's convolutions of `scene`: each lit box (glare/cpu/lit_regions.h, split
// where the PSF cannot cross) with the whole linear convolution kept, as the planned path pads it
// (glare/cpu/float_convolution.h: box + M - 1 each way, the next 2,3,5-smooth length).
std::vector<std::pair<int, int>> convolution_sizes(const ImageRGBA& scene, const GlareSpec& spec, const DisplaySpec& display) {
  const int psf_px = display_psf_size_px(spec.grid_px, psf_degrees_per_pixel(kReferenceWavelengthNm, spec.aperture_width_mm),
                                         DisplayModel(display).degrees_per_pixel_at_centre());
  std::vector<std::pair<int, int>> sizes;
  for (const PixelRect& box : lit_regions(scene, psf_px))
    sizes.emplace_back(smooth_fft_size(box.height_px + psf_px - 1), smooth_fft_size(box.width_px + psf_px - 1));
  return sizes;
}

// A floor is the fastest of at least this many passes: FFTW's threads on a loaded machine wait for
// cores now and then, and one pass costs less than a frame.
constexpr int kFloorRuns = 5;

// The fastest of `runs` passes of the floor's transforms over every size, seconds.
double fftw_floor_s(std::vector<std::unique_ptr<FftwRgbConvolutionFloor>>& floors, int runs) {
  double best = 0.0;
  for (int run = 0; run < runs; ++run) {
    double total = 0.0;
    for (const auto& floor : floors) total += floor->run_s();
    best = run == 0 ? total : std::min(best, total);
  }
  return best;
}

std::vector<RefractionPsfBenchmarkRow> time_refraction_psfs(const DisplaySpec& display, int repeats) {
  const int wavelengths = bench_glare(GlareBackendRequest::cpu).wavelength_samples;
  FftwComplexFloor complex_floor(bench_glare(GlareBackendRequest::cpu).grid_px);
  std::vector<RefractionPsfBenchmarkRow> rows;
  std::optional<Psf> reference;
  // The reference once; the CPU engine's glare (no GL context: "auto" takes the planned path).
  for (const auto& [backend, runs] : {std::pair{GlareBackendRequest::cpu, 1}, std::pair{GlareBackendRequest::automatic, repeats + 1}}) {
    GlareStage stage(bench_glare(backend), display, 1);
    stage.set_refraction(DioptricPower::spherical(-1.0));
    RefractionPsfBenchmarkRow row;
    row.backend = std::string(spelling(stage.backend().kind()));
    std::optional<Psf> first;
    for (int k = 0; k < runs; ++k) {
      const auto start = std::chrono::steady_clock::now();
      std::optional<Psf> psf = stage.display_psf(GlareMode::static_eye, 1.0, 100.0);  // computed anew each call
      const double took_s = seconds_since(start);
      row.psf_s = k == 0 ? took_s : std::min(row.psf_s, took_s);
      if (!first) first = std::move(psf);
    }
    double best = 0.0;
    for (int k = 0; k < 10 * kFloorRuns; ++k) best = k == 0 ? complex_floor.run_s() : std::min(best, complex_floor.run_s());
    row.floor_s = wavelengths * best;
    if (reference) {
      double largest = 0.0, peak = 0.0;
      for (std::size_t i = 0; i < reference->values.size(); ++i) {
        largest = std::max(largest, std::abs(first->values[i] - reference->values[i]));
        peak = std::max(peak, reference->values[i]);
      }
      row.max_error_over_peak = largest / peak;
    } else {
      reference = std::move(first);
    }
    rows.push_back(row);
  }
  return rows;
}

}  // namespace

FrameEngineBenchmarkResult run_frame_engine_benchmark(const FrameEngineBenchmarkOptions& options) {
  if (options.repeats < 1) throw std::invalid_argument("frame engine benchmark: repeats must be at least 1");
  const DisplaySpec display = perception_timing_display(options.width_px, options.height_px);
  const ImageRGBA scene = perception_test_frame(options.width_px, options.height_px);
  const PerceptionSettings stages;  // every stage on
  FrameEngineBenchmarkResult result;
  if (!uses_wave_optics(options.model))
    throw std::invalid_argument("frame engine benchmark: the glare model " + to_string(options.model) +
                                " has no wave-optics part (ritschel, hybrid or human)");
  result.width_px = options.width_px;
  result.height_px = options.height_px;
  result.model = to_string(options.model);
  result.floor_cd_m2 = 1e-4 * display.peak_luminance_cd_m2;
  result.floor_sizes = convolution_sizes(scene, bench_glare(GlareBackendRequest::automatic), display);
  // Planned once (FFTW_MEASURE), before any frame; timed after each engine's frames.
  std::vector<std::unique_ptr<FftwRgbConvolutionFloor>> floors;
  for (const auto& [rows, cols] : result.floor_sizes) floors.push_back(std::make_unique<FftwRgbConvolutionFloor>(rows, cols));
  std::optional<ImageRGBA> reference;
  const auto run = [&](GlareBackendRequest backend, const GlContextFactory& gl_context, int repeats) {
    // The GL engine in one context, as a session's in the display's: its frames stay on the GPU
    // (EyeFrameRequest::on_gpu); the first is read back to be compared.
    std::unique_ptr<GlContext> one_context = gl_context ? gl_context() : nullptr;
    FrameEngine engine(bench_glare(backend, options.model), AdaptationTimeConstants{}, display, 1,
                       one_context ? one_context_factory(*one_context) : GlContextFactory());
    FrameEngineBenchmarkRow row;
    row.engine = std::string(spelling(engine.kind()));
    row.reason = engine.reason();
    ImageRGBA first;
    FrameFacts facts;  // the scene's, kept from frame to frame as a session keeps them
    for (int k = 0; k <= repeats; ++k) {
      EyeFrameRequest request(scene);
      request.facts = &facts;
      request.mode = GlareMode::static_eye;
      request.glared = true;
      request.perception = &stages;
      request.time_s = 1.0 + k / 90.0;
      request.frame_time_s = 1.0 / 90.0;
      request.on_gpu = true;
      const gl::ReadBackTally read_backs_before = gl::read_back_tally();
      const auto start = std::chrono::steady_clock::now();
      EyeFrame frame = engine.frame(request);
      const double took_s = seconds_since(start);
      if (k == 0) {
        row.first_frame_s = took_s;
        first = frame.gpu_image_cd_m2 ? frame.gpu_image_cd_m2->download() : std::move(frame.image_cd_m2);
      } else if (k == 1 || took_s < row.fastest_frame_s) {
        row.fastest_frame_s = took_s;
        row.gpu_stages_s = frame.gpu_stages_s;
        row.read_backs_per_frame = gl::read_back_tally().since(read_backs_before).describe();
      }
    }
    const bool reference_frame = !reference;
    if (reference) {
      // The floor in the same run, right after the frames it stands beside (the machine's load then).
      row.floor_s = fftw_floor_s(floors, std::max(repeats + 1, kFloorRuns));
      row.max_relative_error = max_relative_pixel_error(first, *reference, result.floor_cd_m2);
      row.relative_l2_error = relative_l2_rgb(first, *reference);
    } else {
      reference = std::move(first);
    }
    if (options.progress && !reference_frame)
      options.progress("frame engine " + row.engine + ": first frame " + std::to_string(1e3 * row.first_frame_s) +
                       " ms, fastest " + std::to_string(1e3 * row.fastest_frame_s) + " ms, FFTW floor " +
                       std::to_string(1e3 * row.floor_s) + " ms");
    else if (options.progress)
      options.progress("frame engine reference (float64 glare): " + std::to_string(1e3 * row.first_frame_s) + " ms");
    return row;
  };
  // The reference: the CPU engine with the float64 glare (its first frame only).
  const auto reference_row = run(GlareBackendRequest::cpu, {}, 0);
  result.reference_s = reference_row.first_frame_s;
  // No GL context: the CPU engine, the glare on the planned float32 path, as sessions run it.
  result.rows.push_back(run(GlareBackendRequest::automatic, {}, options.repeats));
  if (options.gl_context) result.rows.push_back(run(GlareBackendRequest::gl, options.gl_context, options.repeats));
  if (options.refraction_rows) result.refraction_rows = time_refraction_psfs(display, options.repeats);
  return result;
}

std::string format_frame_engine_benchmark(const FrameEngineBenchmarkResult& result) {
  std::string text =
      "| engine | first frame ms | fastest frame ms | FFTW floor ms | ratio | relative L2 error | max per-pixel "
      "relative error |\n"
      "|---|---|---|---|---|---|---|\n";
  char line[256];
  for (const FrameEngineBenchmarkRow& row : result.rows) {
    std::snprintf(line, sizeof line, "| %s | %.1f | %.1f | %.2f | %.1f | %.2e | %.2e |\n", row.engine.c_str(),
                  1e3 * row.first_frame_s, 1e3 * row.fastest_frame_s, 1e3 * row.floor_s, row.ratio(),
                  row.relative_l2_error, row.max_relative_error);
    text += line;
  }
  std::string sizes;
  for (const auto& [rows, cols] : result.floor_sizes)
    sizes += (sizes.empty() ? "" : ", ") + std::to_string(cols) + " x " + std::to_string(rows);
  char tail[800];
  std::snprintf(tail, sizeof tail,
                "\n%d x %d, glare %s, per-pixel error floor %.3g cd/m2; the reference (the cpu engine, float64 glare) "
                "took %.1f ms a frame. FFTW floor: 3 forward + 3 inverse real transforms of each padded lit box "
                "(%s)%s, FFTW float, plans made once, measured right after each engine's frames; ratio: fastest "
                "frame over it.\n",
                result.width_px, result.height_px, result.model.c_str(), result.floor_cd_m2, 1e3 * result.reference_s,
                sizes.c_str(), result.model == "ritschel" ? "" : " of the wave-optics part alone");
  text += tail;
  for (const FrameEngineBenchmarkRow& row : result.rows) {
    text += row.reason + "\n";
    if (row.gpu_stages_s.empty()) continue;
    text += "Engine " + row.engine + ", the frame kept on the GPU, its fastest frame: GPU time by stage (timer queries): " +
            describe_gpu_stages(row) + ".\n";
  }
  if (result.refraction_rows.empty()) return text;
  text += "\nThe display PSF with the observer's refraction (-1 D; N = 256, 16 wavelengths, one FFT each with the "
          "eye's LCA), fastest of the repeats, against the FFTW floor of its transforms (16 N x N complex "
          "float64 FFTs, the plan FFTW measures on one thread, divided by the path's 2 threads) and the reference's PSF (max |difference| / peak):\n\n"
          "| glare backend | PSF ms | FFTW floor ms | ratio | max error / peak |\n|---|---|---|---|---|\n";
  for (const RefractionPsfBenchmarkRow& row : result.refraction_rows) {
    std::snprintf(line, sizeof line, "| %s | %.1f | %.2f | %.1f | %.2e |\n", row.backend.c_str(), 1e3 * row.psf_s,
                  1e3 * row.floor_s, row.ratio(), row.max_error_over_peak);
    text += line;
  }
  return text;
}

std::string describe_gpu_stages(const FrameEngineBenchmarkRow& row) {
  if (row.gpu_stages_s.empty()) return {};
  std::string text;
  char part[128];
  for (const auto& [stage, seconds] : row.gpu_stages_s) {
    std::snprintf(part, sizeof part, "%s%s %.2f ms", text.empty() ? "" : ", ", stage.c_str(), 1e3 * seconds);
    text += part;
  }
  return text + "; read back: " + row.read_backs_per_frame;
}

}  // namespace glarelab
