#include "core/clock.h"
#include "glare/glare_benchmark.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <memory>
#include <sstream>
#include <stdexcept>

#include "glare/eye/aperture_raster.h"
#include "glare/cpu/convolution.h"
#include "glare/cpu/float_convolution.h"
#include "glare/cpu/float_psf.h"
#include "glare/cpu/float_spectral_psf.h"
#include "glare/eye/eye_model.h"
#include "glare/cpu/fftw_floor.h"
#include "glare/gl/aperture.h"
#include "glare/gl/convolution.h"
#include "glare/gl/fft.h"
#include "glare/gl/psf.h"
#include "glare/cpu/psf.h"
#include "glare/wave/psf_scale.h"
#include "glare/wave/spectral_psf.h"

namespace glarelab {
namespace {

constexpr double kApertureWidthMm = 10.0;
constexpr double kWavelengthNm = 575.0;  // Ritschel's reference wavelength (section 5)

// Fastest of `repeats` runs of `work` (which must finish its work before returning).
template <typename Work>
double fastest(int repeats, Work&& work) {
  double best = 1e300;
  for (int r = 0; r < std::max(1, repeats); ++r) {
    const auto start = std::chrono::steady_clock::now();
    work();
    best = std::min(best, seconds_since(start));
  }
  return best;
}

template <typename A, typename B>
double relative_l2(const A& test, const B& reference) {
  double difference = 0.0, norm = 0.0;
  for (std::size_t k = 0; k < reference.size(); ++k) {
    const double d = static_cast<double>(test[k]) - static_cast<double>(reference[k]);
    difference += d * d;
    norm += static_cast<double>(reference[k]) * static_cast<double>(reference[k]);
  }
  return norm > 0.0 ? std::sqrt(difference / norm) : 0.0;
}

std::vector<float> rgb_of(const ImageRGBA& image) {
  std::vector<float> values;
  values.reserve(image.rgba.size() / 4 * 3);
  for (std::size_t k = 0; k < image.rgba.size(); ++k)
    if (k % 4 != 3) values.push_back(image.rgba[k]);
  return values;
}

// N x 3N/4 HDR frame: a 1-3 cd/m2 gradient and a 1e5 cd/m2 source of N/64 px, off centre.
ImageRGBA benchmark_frame(int grid_px) {
  ImageRGBA image(grid_px, grid_px * 3 / 4, 0.0f);
  for (int y = 0; y < image.height_px; ++y)
    for (int x = 0; x < image.width_px; ++x) {
      float* p = image.pixel(x, y);
      p[0] = 1.0f + 2.0f * static_cast<float>(x) / static_cast<float>(image.width_px);
      p[1] = 1.5f;
      p[2] = 1.0f + 2.0f * static_cast<float>(y) / static_cast<float>(image.height_px);
    }
  const int side = std::max(1, grid_px / 64), x0 = grid_px * 5 / 8, y0 = image.height_px / 3;
  for (int y = y0; y < y0 + side; ++y)
    for (int x = x0; x < x0 + side; ++x) {
      float* p = image.pixel(x, y);
      p[0] = p[1] = p[2] = 1e5f;
    }
  return image;
}

// The PSF onto display pixels 4 times its own: N/4 pixels across on the frame.
Psf at_display_scale(const Psf& psf) { return resample_psf_to_display(psf, 4.0 * psf.degrees_per_pixel); }

// Central N x N of a 2N PSF (its centre 2N/2 lands on N/2).
std::vector<double> central_crop(const Psf& large, int n) {
  std::vector<double> crop(static_cast<std::size_t>(n) * n);
  const int offset = (large.size_px - n) / 2;
  for (int y = 0; y < n; ++y)
    for (int x = 0; x < n; ++x) crop[static_cast<std::size_t>(y) * n + x] = large.at(0, x + offset, y + offset);
  return crop;
}

struct CpuRun {
  GlareBenchmarkRow row;
  Psf mono, spectral;
  ImageRGBA frame;
};

CpuRun run_cpu(const ApertureGeometry& geometry, int n, FftPrecision precision, const GlareBenchmarkOptions& options) {
  CpuRun run;
  run.row.grid_px = n;
  run.row.backend = precision == FftPrecision::float64 ? GlareBackendKind::cpu_float64 : GlareBackendKind::cpu_float32;
  ApertureRasterOptions raster;
  raster.grid_px = n;
  raster.aperture_width_mm = kApertureWidthMm;
  ApertureGrid grid;
  run.row.aperture_s = fastest(options.repeats, [&] { grid = rasterise_aperture(geometry, raster); });
  MonochromaticPsfOptions mono;
  mono.raster = raster;
  mono.wavelength_nm = kWavelengthNm;
  mono.precision = precision;
  // The eye's whole power error (defocus plus refraction), as a session's PSF takes it; a spherical
  // one is the defocus phase bit for bit (glare/cpu/psf.h).
  const DioptricPower error = geometry.total_power_error();
  (void)compute_monochromatic_psf(grid, geometry.pupil_diameter_mm, error, mono);  // FFTW plans
  run.row.psf_s = fastest(options.repeats, [&] {
    run.mono = compute_monochromatic_psf(grid, geometry.pupil_diameter_mm, error, mono).psf;
  });
  SpectralPsfOptions spectral;
  spectral.wavelength_samples = options.wavelength_samples;
  spectral.reference_wavelength_nm = kWavelengthNm;
  run.row.spectral_s = fastest(options.repeats, [&] { run.spectral = spectral_psf_from_reference(run.mono, spectral).psf; });
  const ImageRGBA frame = benchmark_frame(n);
  const Psf kernel = at_display_scale(run.spectral);
  ConvolutionOptions convolution;
  convolution.precision = precision;
  run.row.convolution_s = fastest(options.repeats, [&] { run.frame = convolve_image_cpu(frame, kernel, convolution); });
  return run;
}

// The planned float32 path (cpu_float_*.h), stage by stage; its spectral PSF is computed at the
// display scale, so its spectral column includes the resampling the other rows leave out.
struct PlannedRun {
  GlareBenchmarkRow row;
  Psf mono, spectral;  // spectral: at the display scale
  ImageRGBA frame;
};

// The planned float32 path's three parts for grid n and the benchmark frame, plans made here.
struct PlannedPath {
  CpuFloatPsf psf;
  CpuFloatSpectralPsf spectral;
  CpuFloatConvolution convolution;
  ImageRGBA scene;

  PlannedPath(int n, const GlareBenchmarkOptions& options)
      : psf(psf_settings(n)),
        spectral(spectral_settings(n, psf.degrees_per_pixel(), options.wavelength_samples)),
        convolution(n, n * 3 / 4, spectral.display_size_px()),
        scene(benchmark_frame(n)) {}

  static CpuFloatPsfSettings psf_settings(int n) {
    CpuFloatPsfSettings settings;
    settings.raster.grid_px = n;
    settings.raster.aperture_width_mm = kApertureWidthMm;
    settings.wavelength_nm = kWavelengthNm;
    return settings;
  }
  static CpuFloatSpectralSettings spectral_settings(int n, double psf_degrees_per_pixel, int wavelength_samples) {
    CpuFloatSpectralSettings settings;
    settings.grid_px = n;
    settings.psf_degrees_per_pixel = psf_degrees_per_pixel;
    settings.display_degrees_per_pixel = 4.0 * psf_degrees_per_pixel;  // as at_display_scale
    settings.wavelength_samples = wavelength_samples;
    settings.reference_wavelength_nm = kWavelengthNm;
    settings.aperture_width_mm = kApertureWidthMm;
    settings.threads = kGlareCpuThreads;
    return settings;
  }
  // One whole frame for the eye's geometry; a new scene transforms the image too.
  void frame(const ApertureGeometry& geometry, bool new_scene, ImageRGBA& out) {
    psf.rasterise(geometry);
    psf.transform(geometry.pupil_diameter_mm, geometry.total_power_error());
    const Psf kernel = spectral.compute(psf.power_column_major(), geometry.pupil_diameter_mm);
    if (new_scene) convolution.set_scene(scene);
    convolution.convolve(kernel, out);
  }
};

PlannedRun run_cpu_planned(const ApertureGeometry& geometry, int n, const GlareBenchmarkOptions& options) {
  PlannedRun run;
  run.row.grid_px = n;
  run.row.backend = GlareBackendKind::cpu_float32_planned;
  PlannedPath path(n, options);
  path.frame(geometry, true, run.frame);  // warm-up
  run.row.aperture_s = fastest(options.repeats, [&] { path.psf.rasterise(geometry); });
  run.row.psf_s =
      fastest(options.repeats, [&] { path.psf.transform(geometry.pupil_diameter_mm, geometry.total_power_error()); });
  run.mono = path.psf.monochromatic_psf();
  run.row.spectral_s = fastest(options.repeats, [&] { run.spectral = path.spectral.compute(path.psf.power_column_major(), geometry.pupil_diameter_mm); });
  run.row.convolution_s = fastest(options.repeats, [&] {
    path.convolution.set_scene(path.scene);
    path.convolution.convolve(run.spectral, run.frame);
  });
  return run;
}

// The eye model's geometry at time_s with the benchmark's refraction error.
ApertureGeometry benchmark_geometry(const EyeModel& eye, double time_s, const GlareBenchmarkOptions& options) {
  ApertureGeometry geometry = eye.geometry_at(time_s);
  geometry.refraction_error = geometry.refraction_error + options.refraction_error;
  return geometry;
}

// Eye geometries 1/60 s apart from time_s on, blinks skipped: one per timed frame.
std::vector<ApertureGeometry> frame_geometries(const EyeModel& eye, double time_s, int count,
                                               const GlareBenchmarkOptions& options) {
  std::vector<ApertureGeometry> geometries;
  for (double t = time_s; static_cast<int>(geometries.size()) < count && t < time_s + 600.0; t += 1.0 / 60.0)
    if (eye.state_at(t).blink_closure == 0.0) geometries.push_back(benchmark_geometry(eye, t, options));
  return geometries;
}

// Whole frames (new scene, static scene) and the FFTW floor, interleaved so that a change of the
// machine's load falls on all three alike; the fastest of each is kept.
GlareFrameRow time_frames(const EyeModel& eye, double time_s, int n, const GlareBenchmarkOptions& options) {
  GlareFrameRow row;
  row.grid_px = n;
  row.threads = kGlareCpuThreads;
  row.frames = std::max(1, options.frames);
  PlannedPath path(n, options);
  row.fft_rows = path.convolution.fft_rows();
  row.fft_cols = path.convolution.fft_cols();
  FftwFloatFloor floor(n, row.fft_rows, row.fft_cols, kGlareCpuThreads);
  const std::vector<ApertureGeometry> geometries = frame_geometries(eye, time_s, 2 * row.frames + 1, options);
  ImageRGBA out;
  path.frame(geometries.front(), true, out);  // warm-up: first touch of every buffer
  floor.run();
  row.floor_s = row.new_scene_s = row.static_scene_s = 1e300;
  for (int k = 0; k < row.frames && 2 * k + 2 < static_cast<int>(geometries.size()); ++k) {
    row.floor_s = std::min(row.floor_s, fastest(1, [&] { floor.run(); }));
    row.new_scene_s = std::min(row.new_scene_s, fastest(1, [&] { path.frame(geometries[2 * k + 1], true, out); }));
    // The scene's spectrum is the one the new-scene frame just made.
    row.static_scene_s = std::min(row.static_scene_s, fastest(1, [&] { path.frame(geometries[2 * k + 2], false, out); }));
  }
  return row;
}

struct GlRun {
  GlareBenchmarkRow row;
  Psf mono, spectral;
  ImageRGBA frame;
};

GlRun run_gl(const ApertureGeometry& geometry, int n, const GlareBenchmarkOptions& options) {
  GlRun run;
  run.row.grid_px = n;
  run.row.backend = GlareBackendKind::gl;
  gl::GlAperture aperture(n, kApertureWidthMm, 2);
  gl::GlPsf psf(n, kApertureWidthMm, 2);
  // Warm-up: llvmpipe compiles each shader at its first dispatch.
  aperture.draw(geometry);
  psf.run_spectral(geometry, options.wavelength_samples, kWavelengthNm);
  glFinish();
  run.row.aperture_s = fastest(options.repeats, [&] {
    aperture.draw(geometry);
    glFinish();
  });
  const double mono_total = fastest(options.repeats, [&] {
    psf.run_monochromatic(geometry, kWavelengthNm);
    glFinish();
  });
  run.mono = psf.read(1, kWavelengthNm);
  const double spectral_total = fastest(options.repeats, [&] {
    psf.run_spectral(geometry, options.wavelength_samples, kWavelengthNm);
    glFinish();
  });
  run.spectral = psf.read(3, kWavelengthNm);
  // GlPsf draws its own aperture: the stages are the differences of the cumulative runs.
  run.row.psf_s = std::max(0.0, mono_total - run.row.aperture_s);
  run.row.spectral_s = std::max(0.0, spectral_total - mono_total);
  const ImageRGBA frame = benchmark_frame(n);
  const Psf kernel = at_display_scale(run.spectral);
  gl::GlConvolution convolution;
  (void)convolution.convolve(frame, kernel);  // warm-up
  // A new PSF each frame (dynamic glare): its spectrum is transformed again on every timed call;
  // a new scene transforms the image again too, a static one keeps its spectrum.
  const auto time_convolution = [&](bool new_scene, double& wall_s, double& gpu_s, std::string& stages) {
    gpu_s = 1e300;
    wall_s = fastest(options.repeats, [&] {
      convolution.forget_psf();
      if (new_scene) convolution.forget_image();
      gl::GlConvolutionReport report;
      run.frame = convolution.convolve(frame, kernel, {}, &report);
      if (report.gpu_s < gpu_s) {
        gpu_s = report.gpu_s;
        stages = report.describe_gpu_stages();
      }
    });
  };
  time_convolution(true, run.row.convolution_s, run.row.convolution_gpu_s, run.row.convolution_gpu_stages);
  time_convolution(false, run.row.static_convolution_s, run.row.static_convolution_gpu_s,
                   run.row.static_convolution_gpu_stages);
  return run;
}

std::string milliseconds(double seconds) {
  char text[32];
  std::snprintf(text, sizeof text, seconds < 0.1 ? "%.1f" : "%.0f", 1e3 * seconds);
  return text;
}

std::string scientific(double value) {
  if (value == 0.0) return "0 (reference)";
  char text[32];
  std::snprintf(text, sizeof text, "%.1e", value);
  return text;
}

}  // namespace

GlareBenchmarkResult run_glare_benchmark(const GlareBenchmarkOptions& options) {
  const auto progress = [&](const std::string& line) {
    if (options.progress) options.progress(line);
  };
  for (int n : options.grid_sizes) {
    if (n < 16 || n % 2 != 0) throw std::invalid_argument("glare benchmark: grid " + std::to_string(n) + " is not an even size >= 16");
    if (options.gl_context && !gl::is_power_of_two_fft_length(n))
      throw std::invalid_argument("glare benchmark: grid " + std::to_string(n) + " is not a GL PSF grid (powers of two 16..4096)");
  }
  GlareBenchmarkResult result;
  // The first instant from time_s on (steps of 0.1 s) with no blink under way: a closing lid would
  // make the aperture, and so the timings, depend on the blink phase.
  const EyeModel eye(EyeParameters{}, options.seed);
  double time_s = options.time_s;
  while (eye.state_at(time_s).blink_closure > 0.0 && time_s < options.time_s + 60.0) time_s += 0.1;
  const ApertureGeometry geometry = benchmark_geometry(eye, time_s, options);
  {
    std::ostringstream text;
    text << "eye model (default parameters) at t = " << time_s << " s (no blink), seed " << options.seed << ": pupil "
         << geometry.pupil_diameter_mm << " mm, " << geometry.discs.size() << " discs, " << geometry.lines.size()
         << " lines, " << geometry.polygons.size() << " polygons; aperture width " << kApertureWidthMm
         << " mm, supersampling 2, " << options.wavelength_samples << " wavelengths";
    result.aperture = text.str();
  }
  std::unique_ptr<GlContext> context;
  if (options.gl_context) {
    context = options.gl_context();
    result.renderer = context->gl_info().renderer;
  }
  for (int n : options.grid_sizes) {
    progress("bench: N = " + std::to_string(n) + ": CPU double reference at 2N = " + std::to_string(2 * n));
    MonochromaticPsfOptions fine;
    fine.raster.grid_px = 2 * n;
    fine.raster.aperture_width_mm = kApertureWidthMm;
    fine.wavelength_nm = kWavelengthNm;
    const std::vector<double> reference_2n = central_crop(compute_monochromatic_psf(geometry, fine).psf, n);

    progress("bench: N = " + std::to_string(n) + ": cpu float64");
    CpuRun reference = run_cpu(geometry, n, FftPrecision::float64, options);
    reference.row.discretisation_error = relative_l2(reference.mono.values, reference_2n);
    const std::vector<float> reference_frame = rgb_of(reference.frame);
    result.rows.push_back(reference.row);

    progress("bench: N = " + std::to_string(n) + ": cpu float32");
    CpuRun single = run_cpu(geometry, n, FftPrecision::float32, options);
    single.row.psf_error = relative_l2(single.mono.values, reference.mono.values);
    single.row.spectral_error = relative_l2(single.spectral.values, reference.spectral.values);
    single.row.frame_error = relative_l2(rgb_of(single.frame), reference_frame);
    single.row.discretisation_error = relative_l2(single.mono.values, reference_2n);
    result.rows.push_back(single.row);

    progress("bench: N = " + std::to_string(n) + ": cpu float32 planned");
    PlannedRun planned = run_cpu_planned(geometry, n, options);
    planned.row.psf_error = relative_l2(planned.mono.values, reference.mono.values);
    planned.row.spectral_error = relative_l2(planned.spectral.values, at_display_scale(reference.spectral).values);
    planned.row.frame_error = relative_l2(rgb_of(planned.frame), reference_frame);
    planned.row.discretisation_error = relative_l2(planned.mono.values, reference_2n);
    result.rows.push_back(planned.row);

    progress("bench: N = " + std::to_string(n) + ": whole frames against the FFTW floor");
    GlareFrameRow frames = time_frames(eye, time_s, n, options);
    frames.frame_error = planned.row.frame_error;
    frames.discretisation_error = planned.row.discretisation_error;
    result.frames.push_back(frames);

    if (options.gl_context) {
      progress("bench: N = " + std::to_string(n) + ": gl on " + result.renderer);
      GlRun gpu = run_gl(geometry, n, options);
      gpu.row.psf_error = relative_l2(gpu.mono.values, reference.mono.values);
      gpu.row.spectral_error = relative_l2(gpu.spectral.values, reference.spectral.values);
      gpu.row.frame_error = relative_l2(rgb_of(gpu.frame), reference_frame);
      gpu.row.discretisation_error = relative_l2(gpu.mono.values, reference_2n);
      result.rows.push_back(gpu.row);
    }
  }
  if (context) context.reset();
  return result;
}

std::string format_glare_benchmark_table(const GlareBenchmarkResult& result) {
  std::ostringstream table;
  table << "| N | backend | aperture ms | FFT+PSF ms | spectral ms | convolution ms (N x 3N/4) | total ms "
           "| PSF error vs CPU double | spectral error vs CPU double | frame error vs CPU double "
           "| PSF error vs 2N reference |\n";
  table << "|---|---|---|---|---|---|---|---|---|---|---|\n";
  for (const GlareBenchmarkRow& row : result.rows)
    table << "| " << row.grid_px << " | " << spelling(row.backend) << " | " << milliseconds(row.aperture_s) << " | "
          << milliseconds(row.psf_s) << " | " << milliseconds(row.spectral_s) << " | " << milliseconds(row.convolution_s)
          << " | " << milliseconds(row.total_s()) << " | " << scientific(row.psf_error) << " | "
          << scientific(row.spectral_error) << " | " << scientific(row.frame_error) << " | "
          << scientific(row.discretisation_error) << " |\n";
  return table.str();
}

std::string format_gl_frame_table(const GlareBenchmarkResult& result) {
  const auto ms = [](double seconds) {
    char text[32];
    std::snprintf(text, sizeof text, "%.3g", 1e3 * seconds);
    return std::string(text);
  };
  std::ostringstream table;
  for (const GlareBenchmarkRow& row : result.rows) {
    if (row.backend != GlareBackendKind::gl) continue;
    if (table.tellp() == 0)
      table << "| N | scene | aperture ms | FFT+PSF ms | spectral ms | convolution GPU ms | convolution wall ms "
               "| frame GPU ms | frame wall ms |\n|---|---|---|---|---|---|---|---|---|\n";
    const double stages_s = row.aperture_s + row.psf_s + row.spectral_s;
    for (const bool new_scene : {true, false}) {
      const double gpu_s = new_scene ? row.convolution_gpu_s : row.static_convolution_gpu_s;
      const double wall_s = new_scene ? row.convolution_s : row.static_convolution_s;
      table << "| " << row.grid_px << " | " << (new_scene ? "new" : "static") << " | " << ms(row.aperture_s) << " | "
            << ms(row.psf_s) << " | " << ms(row.spectral_s) << " | " << ms(gpu_s) << " | " << ms(wall_s) << " | "
            << ms(stages_s + gpu_s) << " | " << ms(stages_s + wall_s) << " |\n";
    }
  }
  for (const GlareBenchmarkRow& row : result.rows)
    if (row.backend == GlareBackendKind::gl && !row.convolution_gpu_stages.empty())
      table << "\nN = " << row.grid_px << ", GL convolution's GPU time by stage, new scene: " << row.convolution_gpu_stages
            << "; static scene: " << row.static_convolution_gpu_stages << "\n";
  return table.str();
}

std::string format_glare_frame_table(const GlareBenchmarkResult& result) {
  std::ostringstream table;
  table << "| N | FFT size (conv.) | threads | FFTW floor ms | new-scene frame ms | ratio | static-scene frame ms "
           "| ratio | frame error vs CPU double | PSF error vs 2N reference |\n";
  table << "|---|---|---|---|---|---|---|---|---|---|\n";
  const auto ratio = [](double value) {
    char text[32];
    std::snprintf(text, sizeof text, "%.2fx", value);
    return std::string(text);
  };
  for (const GlareFrameRow& row : result.frames)
    table << "| " << row.grid_px << " | " << row.fft_rows << " x " << row.fft_cols << " | " << row.threads << " | "
          << milliseconds(row.floor_s) << " | " << milliseconds(row.new_scene_s) << " | " << ratio(row.new_scene_ratio())
          << " | " << milliseconds(row.static_scene_s) << " | " << ratio(row.static_scene_ratio()) << " | "
          << scientific(row.frame_error) << " | " << scientific(row.discretisation_error) << " |\n";
  return table.str();
}

}  // namespace glarelab
