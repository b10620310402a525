#include "stimuli/cpu_stage_benchmark.h"

#include <algorithm>
#include <cstddef>
#include <iomanip>
#include <sstream>
#include <stdexcept>

#include "core/clock.h"
#include "core/parallel_for.h"
#include "core/streaming_floor.h"
#include "glare/eye/pupil_model.h"
#include "glare/refraction/spectacle_lens.h"
#include "stimuli/perception/acuity_loss_float.h"
#include "stimuli/perception/perception_stages.h"
#include "stimuli/perception/perception_stages_float.h"
#include "stimuli/perception/stage_timing.h"
#include "stimuli/spectacle_warp.h"

namespace glarelab {
namespace {

constexpr double kGaze[2] = {0.45, 0.4};
constexpr double kFrameTimeS = 1.0 / 90.0;
constexpr double kSceneFloorCdM2 = 1e-6;

struct Times {
  double best_s = 0.0, median_s = 0.0;
  double cpu_best_s = 0.0;  // the process' CPU time (all threads) of its least costly run
};

Times summarise(const std::vector<CallTimes>& runs) {
  std::vector<double> wall;
  double cpu_best_s = runs.front().cpu_s;
  for (const CallTimes& run : runs) {
    wall.push_back(run.wall_s);
    cpu_best_s = std::min(cpu_best_s, run.cpu_s);
  }
  std::sort(wall.begin(), wall.end());
  return {wall.front(), wall[wall.size() / 2], cpu_best_s};
}

struct StageAndFloor {
  Times stage, floor;
};

// `repeats` times: `prepare` (untimed), then `work` and its floor one right after the other, timed
// alike. A shared machine's speed drifts over the seconds a bench takes (other guests' memory
// traffic, the host's clock); a floor measured beside each run of its stage sees the machine the
// stage saw, where one measured once at the start would not.
template <typename Prepare, typename Work, typename Floor>
StageAndFloor time_beside_floor(int repeats, Prepare prepare, Work work, Floor floor) {
  std::vector<CallTimes> stage_runs, floor_runs;
  for (int r = 0; r < repeats; ++r) {
    prepare();
    stage_runs.push_back(time_call(work));
    floor_runs.push_back(time_call(floor));
  }
  return {summarise(stage_runs), summarise(floor_runs)};
}

CpuStageBenchmarkRow make_row(const std::string& stage, const StageAndFloor& times, double error, double error_floor,
                              double thesis_ms = -1.0) {
  const Times& stage_times = times.stage;
  const Times& floor = times.floor;
  CpuStageBenchmarkRow row;
  row.stage = stage;
  row.best_s = stage_times.best_s;
  row.median_s = stage_times.median_s;
  row.floor_best_s = floor.best_s;
  row.floor_median_s = floor.median_s;
  row.cpu_best_s = stage_times.cpu_best_s;
  row.floor_cpu_best_s = floor.cpu_best_s;
  row.max_relative_error = error;
  row.error_floor = error_floor;
  row.thesis_gtx1070_ms = thesis_ms;
  return row;
}

}  // namespace

CpuStageBenchmarkResult run_cpu_stage_benchmark(const CpuStageBenchmarkOptions& options) {
  if (options.width_px < 16 || options.height_px < 16 || options.repeats < 1)
    throw std::invalid_argument("cpu stage benchmark: the frame must be at least 16 x 16 and repeats >= 1");
  CpuStageBenchmarkResult result;
  result.width_px = options.width_px;
  result.height_px = options.height_px;
  result.threads = static_cast<int>(resolved_threads(static_cast<unsigned>(std::max(options.threads, 0))));
  const int threads = result.threads, repeats = options.repeats;
  const std::size_t frame_bytes = 4 * sizeof(float) * static_cast<std::size_t>(options.width_px) * options.height_px;

  DisplaySpec display;
  display.width_px = options.width_px;
  display.height_px = options.height_px;
  const PerceptionSettings settings;
  const double display_floor = 1e-4 * display.peak_luminance_cd_m2;
  const ImageRGBA scene = perception_test_frame(options.width_px, options.height_px);
  ImageRGBA work = scene;
  const auto reset = [&] { std::copy(scene.rgba.begin(), scene.rgba.end(), work.rgba.begin()); };
  StreamingFloor read_floor(frame_bytes, 0, threads), read_write_floor(frame_bytes, frame_bytes, threads);
  read_floor.run_s();  // pages mapped, caches warm
  read_write_floor.run_s();
  const auto reads = [&] { read_floor.run_s(); };
  const auto reads_and_writes = [&] { read_write_floor.run_s(); };

  // Adaptation: a scalar, its error relative.
  double adapted = 0.0;
  const StageAndFloor adaptation = time_beside_floor(
      repeats, [] {},
      [&] { adapted = frame_adaptation_luminance_float_cd_m2(scene, kGaze[0], kGaze[1], settings.adaptation_weighting, threads); },
      reads);
  const double adapted_reference = frame_adaptation_luminance_cd_m2(scene, kGaze[0], kGaze[1], settings.adaptation_weighting);
  result.rows.push_back(make_row("adaptation", adaptation,
                                 std::abs(adapted - adapted_reference) / adapted_reference, 0.0, 0.18));

  const double ppd = display_pixels_per_degree(display);
  const StageAndFloor acuity = time_beside_floor(
      repeats, reset, [&] { apply_acuity_loss_float(work, settings.acuity_settings, ppd, threads); }, reads_and_writes);
  const ImageRGBA blurred = apply_acuity_loss(scene, settings.acuity_settings, ppd);
  result.rows.push_back(make_row("acuity", acuity,
                                 max_relative_pixel_error(work, blurred, kSceneFloorCdM2), kSceneFloorCdM2, 0.36));

  const auto from_blurred = [&] { std::copy(blurred.rgba.begin(), blurred.rgba.end(), work.rgba.begin()); };
  const StageAndFloor tone = time_beside_floor(
      repeats, from_blurred,
      [&] { tone_map_float(work, adapted_reference, settings.tone_mapping_settings, display.peak_luminance_cd_m2, threads); },
      reads_and_writes);
  const ImageRGBA mapped = tone_map(blurred, adapted_reference, settings.tone_mapping_settings, display.peak_luminance_cd_m2);
  result.rows.push_back(make_row("tone_mapping " + to_string(settings.tone_mapping_settings.curve), tone,
                                 max_relative_pixel_error(work, mapped, display_floor), display_floor));

  const double rods = rod_sensitivity(adapted_reference, settings.adaptation_time_constants.rod_half_sensitivity_cd_m2);
  const auto from_mapped = [&] { std::copy(mapped.rgba.begin(), mapped.rgba.end(), work.rgba.begin()); };
  const StageAndFloor scotopic = time_beside_floor(
      repeats, from_mapped, [&] { apply_scotopic_colour_float(work, rods, settings.scotopic_settings, threads); },
      reads_and_writes);
  const ImageRGBA shifted = apply_scotopic_colour(mapped, rods, settings.scotopic_settings);
  result.rows.push_back(make_row("scotopic " + to_string(settings.scotopic_settings.form), scotopic,
                                 max_relative_pixel_error(work, shifted, display_floor), display_floor, 0.14));

  // The chain, from the scene to the display frame, against the sum of the four floors.
  PerceptionResult chain_result;
  const StageAndFloor chain = time_beside_floor(
      repeats, [] {},
      [&] {
        TemporalAdaptation eye(adapted_reference, settings.adaptation_time_constants);
        chain_result = run_perception_stages_float(scene, {kGaze[0], kGaze[1], kFrameTimeS}, eye, settings, display, {}, threads);
      },
      [&] {
        read_floor.run_s();
        for (int stage = 0; stage < 3; ++stage) read_write_floor.run_s();
      });
  TemporalAdaptation reference_eye(adapted_reference, settings.adaptation_time_constants);
  const PerceptionResult chain_reference =
      run_perception_stages(scene, {kGaze[0], kGaze[1], kFrameTimeS}, reference_eye, settings, display);
  result.rows.push_back(make_row("all perception stages", chain,
                                 max_relative_pixel_error(chain_result.image, chain_reference.image, display_floor),
                                 display_floor, 2.42));

  // The spectacle warp: a -6.00 DS lens, the frame 30.7 deg across (the warp bench's field of view,
  // bench/spectacle_warp_bench.cpp, which the lens covers).
  SpectacleLensSpec lens_spec;
  lens_spec.prescription = {-6.0, 0.0, 0.0};
  const SpectacleLens lens(lens_spec);
  const SpectacleFrame frame{options.width_px, options.height_px, 30.72 / options.width_px};
  SpectacleWarpOptions warp_options;
  warp_options.scene_distance_mm = display.viewing_distance_mm;
  warp_options.threads = threads;
  ImageRGBA warped;
  // Into a frame reused from run to run, as the floor's buffers are; the grids traced once and kept,
  // as a session keeps them while its lens and display stay the same (SpectacleWarpGridCache), and,
  // in a row of its own, traced for each frame.
  const SpectacleWarpGrids grids(lens, frame, warp_options);
  const StageAndFloor warp =
      time_beside_floor(repeats, [] {}, [&] { warp_through_spectacles(scene, grids, warp_options, warped); }, reads_and_writes);
  const ImageRGBA warped_reference = warp_through_spectacles_reference(scene, lens, frame, warp_options);
  result.rows.push_back(make_row("spectacle warp -6.00 DS", warp,
                                 max_relative_pixel_error(warped, warped_reference, kSceneFloorCdM2), kSceneFloorCdM2));
  const StageAndFloor warp_traced = time_beside_floor(
      repeats, [] {}, [&] { warp_through_spectacles(scene, lens, frame, warp_options, warped); }, reads_and_writes);
  result.rows.push_back(make_row("spectacle warp -6.00 DS, grids traced each frame", warp_traced,
                                 max_relative_pixel_error(warped, warped_reference, kSceneFloorCdM2), kSceneFloorCdM2));
  return result;
}

std::string format_cpu_stage_benchmark(const CpuStageBenchmarkResult& result) {
  std::ostringstream out;
  out << result.width_px << " x " << result.height_px << ", " << result.threads
      << " threads; wall clock (best and median of the repeats) and the process' CPU time over all threads "
         "(the least of the repeats; other processes on a shared machine do not inflate it); floor: streaming the bytes the stage must read and write once, the same threads "
         "(core/streaming_floor.h); error: against the float64 reference.\n\n"
      << "| stage | best ms | median ms | floor best ms | floor median ms | ratio (best) | CPU ms, stage / floor | ratio (CPU) | max error | error floor cd/m2 | thesis GTX 1070 ms |\n"
      << "|---|---|---|---|---|---|---|---|---|---|---|\n";
  out << std::setprecision(3);
  for (const CpuStageBenchmarkRow& row : result.rows) {
    out << "| " << row.stage << " | " << 1e3 * row.best_s << " | " << 1e3 * row.median_s << " | " << 1e3 * row.floor_best_s
        << " | " << 1e3 * row.floor_median_s << " | " << (row.floor_best_s > 0.0 ? row.best_s / row.floor_best_s : 0.0)
        << " | " << 1e3 * row.cpu_best_s << " / " << 1e3 * row.floor_cpu_best_s << " | "
        << (row.floor_cpu_best_s > 0.0 ? row.cpu_best_s / row.floor_cpu_best_s : 0.0) << " | " << row.max_relative_error << " | " << row.error_floor << " | ";
    if (row.thesis_gtx1070_ms >= 0.0)
      out << row.thesis_gtx1070_ms;
    else
      out << "-";
    out << " |\n";
  }
  return out.str();
}

}  // namespace glarelab
