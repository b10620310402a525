#include "stimuli/perception/stage_timing.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstddef>
#include <iomanip>
#include <memory>
#include <sstream>
#include <stdexcept>

#include "core/gl/shader_program.h"
#include "core/random.h"
#include "glare/eye/pupil_model.h"
#include "stimuli/perception/gl_perception_stages.h"
#include "stimuli/perception/perception_stages.h"

namespace glarelab {
namespace {

constexpr double kSceneFloorCdM2 = 1e-6;
constexpr double kDisplayFloorOfPeak = 1e-4;
constexpr double kGaze[2] = {0.45, 0.4};
constexpr double kFrameTimeS = 1.0 / 90.0;

// Fastest of `repeats` runs of `work`, in seconds.
template <typename Work>
double fastest_s(int repeats, Work work) {
  double best = 0.0;
  for (int r = 0; r < repeats; ++r) {
    const auto start = std::chrono::steady_clock::now();
    work();
    const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    best = r == 0 ? elapsed : std::min(best, elapsed);
  }
  return best;
}

std::string tone_name(ToneCurve curve) { return "tone_mapping " + to_string(curve); }
std::string scotopic_name(ScotopicForm form) { return "scotopic " + to_string(form); }

}  // namespace

ImageRGBA perception_test_frame(int width_px, int height_px, std::uint64_t seed) {
  if (width_px < 1 || height_px < 1) throw std::invalid_argument("perception test frame: the size must be at least 1 x 1");
  const CounterRandom random(seed, RandomStream::glare_gl_test_input);
  ImageRGBA frame(width_px, height_px, 1.0f);
  const auto put = [&](int x, int y, double luminance, const double colour[3]) {
    // colour scaled so that its Eq. 5.1 luminance is `luminance`.
    const double scale = luminance / (0.2125 * colour[0] + 0.7154 * colour[1] + 0.0721 * colour[2]);
    float* p = frame.pixel(x, y);
    for (int c = 0; c < 3; ++c) p[c] = static_cast<float>(scale * colour[c]);
  };
  for (int y = 0; y < height_px; ++y)
    for (int x = 0; x < width_px; ++x) {
      const std::uint64_t pixel = static_cast<std::uint64_t>(y) * width_px + x;
      // 8 x 8 patches of one colour, each channel 0.05..1 (some nearly pure primaries).
      const std::uint64_t patch = static_cast<std::uint64_t>(y / 8) * ((width_px + 7) / 8) + x / 8;
      const double colour[3] = {0.05 + 0.95 * random.uniform(patch, 1), 0.05 + 0.95 * random.uniform(patch, 2),
                                0.05 + 0.95 * random.uniform(patch, 3)};
      // 1e-3 cd/m2 at the left edge to 2.5e3 at the right, times a texture of 1..1.5.
      const double ramp = width_px > 1 ? static_cast<double>(x) / (width_px - 1) : 0.0;
      put(x, y, 1e-3 * std::pow(10.0, 6.4 * ramp) * (1.0 + 0.5 * random.uniform(pixel, 0)), colour);
    }
  // Sharp edges in the dark part: a neutral 1e3 cd/m2 rectangle.
  const double grey[3] = {1.0, 1.0, 1.0};
  for (int y = 3 * height_px / 10; y < height_px / 2; ++y)
    for (int x = width_px / 10; x < width_px / 5; ++x) put(x, y, 1e3, grey);
  // A bright warm source of 1e4 cd/m2, also in the dark part.
  const double warm[3] = {1.0, 0.85, 0.6};
  const double cx = 0.3 * width_px, cy = 0.6 * height_px, radius = std::max(1.0, 0.015 * width_px);
  for (int y = 0; y < height_px; ++y)
    for (int x = 0; x < width_px; ++x)
      if (std::hypot(x + 0.5 - cx, y + 0.5 - cy) <= radius) put(x, y, 1e4, warm);
  return frame;
}

double max_relative_pixel_error(const ImageRGBA& actual, const ImageRGBA& expected, double floor) {
  if (actual.width_px != expected.width_px || actual.height_px != expected.height_px)
    throw std::invalid_argument("perception comparison: the images differ in size");
  double worst = 0.0;
  for (int y = 0; y < expected.height_px; ++y)
    for (int x = 0; x < expected.width_px; ++x) {
      const float* a = actual.pixel(x, y);
      const float* e = expected.pixel(x, y);
      double scale = floor, error = 0.0;
      for (int c = 0; c < 3; ++c) {
        scale = std::max(scale, std::abs(static_cast<double>(e[c])));
        error = std::max(error, std::abs(static_cast<double>(a[c]) - e[c]));
      }
      // NaN anywhere counts as the worst error.
      if (!(error / scale <= worst)) worst = std::isnan(error) ? INFINITY : error / scale;
    }
  return worst;
}

double relative_l2_rgb(const ImageRGBA& actual, const ImageRGBA& expected) {
  double difference = 0.0, norm = 0.0;
  for (std::size_t i = 0; i < expected.rgba.size(); ++i) {
    if (i % 4 == 3) continue;
    const double e = expected.rgba[i], d = static_cast<double>(actual.rgba[i]) - e;
    difference += d * d;
    norm += e * e;
  }
  return norm > 0.0 ? std::sqrt(difference / norm) : std::sqrt(difference);
}

DisplaySpec perception_timing_display(const PerceptionTimingOptions& options) {
  DisplaySpec display;
  display.width_px = options.width_px;
  display.height_px = options.height_px;
  display.viewing_distance_mm = options.viewing_distance_mm;
  display.pixel_pitch_mm = options.pixel_pitch_mm;
  display.peak_luminance_cd_m2 = options.peak_luminance_cd_m2;
  return display;
}

DisplaySpec perception_timing_display(int width_px, int height_px) {
  PerceptionTimingOptions options;
  options.width_px = width_px;
  options.height_px = height_px;
  return perception_timing_display(options);
}

PerceptionTimingResult time_perception_stages(const PerceptionTimingOptions& options) {
  if (options.width_px < 16 || options.height_px < 16 || options.width_px > 8192 || options.height_px > 8192)
    throw std::invalid_argument("perception timing: the frame must be 16 x 16 to 8192 x 8192 (got " +
                                std::to_string(options.width_px) + " x " + std::to_string(options.height_px) + ")");
  if (options.repeats < 1) throw std::invalid_argument("perception timing: repeats must be >= 1");
  const auto progress = [&](const std::string& line) {
    if (options.progress) options.progress(line);
  };
  PerceptionTimingResult result;
  result.width_px = options.width_px;
  result.height_px = options.height_px;
  const DisplaySpec display = perception_timing_display(options);
  const double ppd = display_pixels_per_degree(display);
  result.pixels_per_degree = ppd;
  const PerceptionSettings settings;
  const double display_floor = kDisplayFloorOfPeak * options.peak_luminance_cd_m2;

  const ImageRGBA frame = perception_test_frame(options.width_px, options.height_px);
  const double frame_luminance = frame_adaptation_luminance_cd_m2(frame, kGaze[0], kGaze[1]);
  result.adapted_luminance_cd_m2 = frame_luminance;
  const double rod = rod_sensitivity(frame_luminance, settings.adaptation_time_constants.rod_half_sensitivity_cd_m2);

  // CPU rows, keeping each stage's output as the next stage's input on both paths.
  progress("perception timing: CPU adaptation");
  PerceptionTimingRow adaptation{"adaptation", 0, 0, 0, 0, 0.18};
  adaptation.cpu_s = fastest_s(options.repeats, [&] {
    TemporalAdaptation eye(1.0);
    eye.advance(frame_adaptation_luminance_cd_m2(frame, kGaze[0], kGaze[1]), kFrameTimeS);
  });
  progress("perception timing: CPU acuity");
  ImageRGBA blurred;
  PerceptionTimingRow acuity{"acuity", 0, 0, 0, kSceneFloorCdM2, 0.36};
  acuity.cpu_s = fastest_s(options.repeats, [&] { blurred = apply_acuity_loss(frame, settings.acuity_settings, ppd); });
  std::vector<PerceptionTimingRow> tone_rows, scotopic_rows;
  std::vector<ImageRGBA> tone_outputs, scotopic_outputs;
  for (ToneCurve curve : {ToneCurve::aces_narkowicz, ToneCurve::aces_hill}) {
    progress("perception timing: CPU " + tone_name(curve));
    ToneMappingSettings tone = settings.tone_mapping_settings;
    tone.curve = curve;
    ImageRGBA mapped;
    PerceptionTimingRow row{tone_name(curve), 0, 0, 0, display_floor, -1.0};
    row.cpu_s = fastest_s(options.repeats,
                          [&] { mapped = tone_map(blurred, frame_luminance, tone, options.peak_luminance_cd_m2); });
    tone_rows.push_back(row);
    tone_outputs.push_back(std::move(mapped));
  }
  for (ScotopicForm form : {ScotopicForm::luidolt_tint, ScotopicForm::spencer_desaturation}) {
    progress("perception timing: CPU " + scotopic_name(form));
    ScotopicSettings scotopic = settings.scotopic_settings;
    scotopic.form = form;
    ImageRGBA shifted;
    PerceptionTimingRow row{scotopic_name(form), 0, 0, 0, display_floor, 0.14};
    row.cpu_s = fastest_s(options.repeats, [&] { shifted = apply_scotopic_colour(tone_outputs[0], rod, scotopic); });
    scotopic_rows.push_back(row);
    scotopic_outputs.push_back(std::move(shifted));
  }
  progress("perception timing: CPU all stages");
  PerceptionResult chain;
  PerceptionTimingRow all{"all stages", 0, 0, 0, display_floor, -1.0};
  all.cpu_s = fastest_s(options.repeats, [&] {
    TemporalAdaptation eye(1.0);
    chain = run_perception_stages(frame, {kGaze[0], kGaze[1], kFrameTimeS}, eye, settings, display);
  });

  if (options.gl_context) {
    const std::unique_ptr<GlContext> context = options.gl_context();
    result.renderer = context->gl_info().describe();
    const auto gl_fastest = [&](auto work) {
      work();  // first run outside the timing: shader compilation and buffer allocation
      glFinish();
      return fastest_s(options.repeats, [&] {
        work();
        glFinish();
      });
    };
    gl::GlFrameBuffer input(frame), output(options.width_px, options.height_px);
    {
      progress("perception timing: GL adaptation");
      gl::GlFrameAdaptationLuminance stage;
      double luminance = 0.0;
      adaptation.gl_s = gl_fastest([&] {
        TemporalAdaptation eye(1.0);
        luminance = stage.luminance_cd_m2(input, kGaze[0], kGaze[1]);
        eye.advance(luminance, kFrameTimeS);
      });
      adaptation.max_relative_error = std::abs(luminance - frame_luminance) / frame_luminance;
    }
    {
      progress("perception timing: GL acuity");
      gl::GlAcuityLoss stage;
      acuity.gl_s = gl_fastest([&] { stage.apply(input, settings.acuity_settings, ppd, output); });
      acuity.max_relative_error = max_relative_pixel_error(output.download(), blurred, kSceneFloorCdM2);
    }
    {
      gl::GlToneMapping stage;
      input.upload(blurred);
      for (std::size_t k = 0; k < tone_rows.size(); ++k) {
        progress("perception timing: GL " + tone_rows[k].stage);
        ToneMappingSettings tone = settings.tone_mapping_settings;
        tone.curve = k == 0 ? ToneCurve::aces_narkowicz : ToneCurve::aces_hill;
        tone_rows[k].gl_s =
            gl_fastest([&] { stage.apply(input, frame_luminance, tone, options.peak_luminance_cd_m2, output); });
        tone_rows[k].max_relative_error = max_relative_pixel_error(output.download(), tone_outputs[k], display_floor);
      }
    }
    {
      gl::GlScotopicColour stage;
      input.upload(tone_outputs[0]);
      for (std::size_t k = 0; k < scotopic_rows.size(); ++k) {
        progress("perception timing: GL " + scotopic_rows[k].stage);
        ScotopicSettings scotopic = settings.scotopic_settings;
        scotopic.form = k == 0 ? ScotopicForm::luidolt_tint : ScotopicForm::spencer_desaturation;
        scotopic_rows[k].gl_s = gl_fastest([&] { stage.apply(input, rod, scotopic, output); });
        scotopic_rows[k].max_relative_error =
            max_relative_pixel_error(output.download(), scotopic_outputs[k], display_floor);
      }
    }
    {
      progress("perception timing: GL all stages");
      gl::GlPerceptionStages stages;
      PerceptionResult gl_chain;
      all.gl_s = gl_fastest([&] {
        TemporalAdaptation eye(1.0);
        gl_chain = stages.run(frame, {kGaze[0], kGaze[1], kFrameTimeS}, eye, settings, display);
      });
      all.max_relative_error = max_relative_pixel_error(gl_chain.image, chain.image, display_floor);
    }
    gl::check_gl_error("perception timing");
  }
  result.rows.push_back(adaptation);
  result.rows.push_back(acuity);
  result.rows.insert(result.rows.end(), tone_rows.begin(), tone_rows.end());
  result.rows.insert(result.rows.end(), scotopic_rows.begin(), scotopic_rows.end());
  result.rows.push_back(all);
  return result;
}

std::string format_perception_timing(const PerceptionTimingResult& result) {
  std::ostringstream text;
  text << "Perception stages (Luidolt 2020) on a " << result.width_px << " x " << result.height_px
       << " frame (0.001 to 1e4 cd/m2), " << std::setprecision(3) << result.pixels_per_degree
       << " px/deg, adapted to " << result.adapted_luminance_cd_m2 << " cd/m2"
       << (result.renderer.empty() ? "" : "; OpenGL: " + result.renderer) << ".\n\n";
  text << "| stage | CPU double ms | GL ms | thesis GTX 1070 ms (1440 x 1600) | max rel. error GL vs CPU | floor |\n";
  text << "|---|---|---|---|---|---|\n";
  const bool gl = !result.renderer.empty();
  for (const PerceptionTimingRow& row : result.rows) {
    text << "| " << row.stage << " | " << std::fixed << std::setprecision(2) << row.cpu_s * 1e3 << " | ";
    if (gl)
      text << row.gl_s * 1e3;
    else
      text << "-";
    text << " | ";
    if (row.thesis_gtx1070_ms >= 0.0)
      text << row.thesis_gtx1070_ms;
    else
      text << "-";
    text << " | " << std::scientific << std::setprecision(1);
    if (gl)
      text << row.max_relative_error;
    else
      text << "-";
    text << " | ";
    if (row.floor > 0.0)
      text << row.floor << " cd/m2";
    else
      text << "- (scalar)";
    text << " |\n" << std::defaultfloat;
  }
  return text.str();
}

}  // namespace glarelab
