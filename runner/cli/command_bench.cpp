// glarelab bench: speed against error of the glare stages on both compute backends, per grid size
// (glare/glare_benchmark.h), as a Markdown table on stdout; progress on stderr.
#include <cstdio>
#include <fstream>
#include <iostream>
#include <memory>
#include <string>
#include <vector>

#include "glare/glare_backend.h"
#include "glare/analytic/analytic_two_level_benchmark.h"
#include "glare/glare_benchmark.h"
#include "glare/gl/fft.h"
#include "core/errors.h"
#include "stimuli/cpu_stage_benchmark.h"
#include "stimuli/depth_of_field_benchmark.h"
#include "stimuli/glare_model_benchmark.h"
#include "stimuli/perception/stage_timing.h"
#include "runner/cli/bench_memory.h"
#include "stimuli/frame_engine.h"
#include "stimuli/frame_engine_benchmark.h"
#include "stimuli/whole_frame_benchmark.h"
#include "runner/cli/commands.h"
#include "runner/cli/option_checks.h"
#include "runner/display/compute_context.h"

namespace glarelab::cli {
namespace {

struct BenchArguments {
  bool quick = false;
  bool no_gl = false;
  FrameEngineRequest engine = FrameEngineRequest::automatic;  // --engine, read when given
  std::vector<int> grids;  // empty: 256, 512, 1024 (and 2048 without --quick)
  int repeats = 0;  // 0: 1 with --quick, else 3
  int frames = 0;   // 0: 5 with --quick, else 10
  bool analytic_only = false;
  bool no_analytic = false;
  std::vector<int> analytic_size = {1920, 1080};
  bool perception_only = false;
  bool depth_of_field_only = false;
  bool memory_only = false;
  std::vector<int> memory_size = {1920, 1080};
  int memory_frames = 30;
  std::string memory_child;  // hidden: this process is a memory row's child (runner/cli/bench_memory.h)
};

// The 1, 5 and 15 minute load averages as "a, b, c"; empty where /proc/loadavg cannot be read.
std::string load_average() {
  std::ifstream loadavg("/proc/loadavg");
  if (std::string one, five, fifteen; loadavg >> one >> five >> fifteen) return one + ", " + five + ", " + fifteen;
  return {};
}

void print_load_average(const std::string& where, const std::string& averages = load_average()) {
  if (!averages.empty()) std::cout << "Load average (1, 5, 15 min) at the end of " << where << ": " << averages << ".\n";
}

// Luidolt 2020's perception stages at 1920 x 1080, CPU double and GL, with their agreement, beside
// the thesis' GTX 1070 figures (stimuli/perception/stage_timing.h).
void print_perception_rows(const BenchArguments& args) {
  PerceptionTimingOptions options;
  options.repeats = args.repeats > 0 ? args.repeats : (args.quick ? 1 : 3);
  if (!args.no_gl) options.gl_context = gl::compute_context_factory();
  options.progress = [](const std::string& line) { std::cerr << line << std::endl; };
  std::cout << "Perception stages (Luidolt 2020, Fig. 6.1), one eye, CPU double reference and GL; agreement "
               "is the largest per-pixel error of GL against the CPU, relative to the CPU pixel.\n\n"
            << format_perception_timing(time_perception_stages(options));
  print_load_average("the perception rows");
  CpuStageBenchmarkOptions floors;
  if (args.repeats > 0) floors.repeats = args.repeats;
  std::cout << "\nThe CPU engine's float32 stages (what sessions run) beside their floors measured in the same run "
               "(stimuli/cpu_stage_benchmark.h).\n\n"
            << format_cpu_stage_benchmark(run_cpu_stage_benchmark(floors));
  print_load_average("the CPU stage rows");
}

// The GPU engine at its targets: one eye's 1920 x 1080 frame with the hybrid eye's glare (Ritschel
// near, Spencer far) and every perception stage, which should take at most 2 ms on an H100/H200-class
// GPU, and one eye's frame of a headset (1440 x 1600), two of which must fit the 11.1 ms of 90 Hz.
// Each through both engines (stimuli/frame_engine_benchmark.h), the GL frame kept on the GPU.
void print_gpu_target_rows(const BenchArguments& args) {
  std::cout << "\nThe engines at the GPU's targets: the hybrid eye's glare (Ritschel near, Spencer far) and every "
               "perception stage, the GL frame kept on the GPU; the fastest frame of the repeats; error against "
               "the CPU engine with the float64 glare.\n\n"
               "| frame | engine | fastest frame ms | relative L2 error | max per-pixel relative error |\n"
               "|---|---|---|---|---|\n";
  struct Target {
    int width_px, height_px;
    double gl_frame_s = 0.0;
  };
  Target desktop{1920, 1080}, headset_eye{1440, 1600};
  std::vector<std::string> stage_lines;
  for (Target* target : {&desktop, &headset_eye}) {
    const int width_px = target->width_px, height_px = target->height_px;
    FrameEngineBenchmarkOptions options;
    options.width_px = width_px;
    options.height_px = height_px;
    options.model = GlareModel::hybrid;
    options.refraction_rows = false;
    options.repeats = args.repeats > 0 ? args.repeats : (args.quick ? 1 : 3);
    options.gl_context = gl::compute_context_factory();
    options.progress = [](const std::string& line) { std::cerr << line << std::endl; };
    const FrameEngineBenchmarkResult result = run_frame_engine_benchmark(options);
    for (const FrameEngineBenchmarkRow& row : result.rows) {
      char line[256];
      std::snprintf(line, sizeof line, "| %d x %d | %s | %.2f | %.2e | %.2e |\n", width_px, height_px, row.engine.c_str(),
                    1e3 * row.fastest_frame_s, row.relative_l2_error, row.max_relative_error);
      std::cout << line;
      if (row.engine != "gl") continue;
      target->gl_frame_s = row.fastest_frame_s;
      stage_lines.push_back(std::to_string(width_px) + " x " + std::to_string(height_px) +
                            ", GL, GPU time by stage: " + describe_gpu_stages(row) + ".");
    }
  }
  std::cout << "\n";
  for (const std::string& line : stage_lines) std::cout << line << "\n";
  char summary[320];
  std::snprintf(summary, sizeof summary,
                "GL engine: 1920 x 1080 with hybrid glare and every perception stage %.2f ms a frame (2 ms asked); "
                "two eyes of 1440 x 1600 made one after the other 2 x %.2f = %.2f ms (the 11.1 ms of 90 Hz).\n",
                1e3 * desktop.gl_frame_s, 1e3 * headset_eye.gl_frame_s, 2e3 * headset_eye.gl_frame_s);
  std::cout << summary;
  print_load_average("the GPU target rows");
}

// One eye's whole frame (static glare and every perception stage) through each frame engine
// (stimuli/frame_engine_benchmark.h).
void print_frame_engine_rows(const BenchArguments& args) {
  FrameEngineBenchmarkOptions options;
  options.repeats = args.repeats > 0 ? args.repeats : (args.quick ? 1 : 3);
  if (!args.no_gl) options.gl_context = gl::compute_context_factory();
  options.progress = [](const std::string& line) { std::cerr << line << std::endl; };
  std::cout << "Frame engines: one eye's frame, static Ritschel glare (N = 256, 16 wavelengths) between adaptation "
               "and acuity and every perception stage, on the perception rows' frame; each frame against the CPU "
               "engine's with the float64 glare by the perception rows' metric.\n\n"
            << format_frame_engine_benchmark(run_frame_engine_benchmark(options));
  print_load_average("the frame engine rows");
  // Asked for by name (as scripts/gpu_check.sh does): on llvmpipe these frames take seconds each.
  if (args.engine == FrameEngineRequest::gpu && !args.no_gl) print_gpu_target_rows(args);
  WholeFrameBenchmarkOptions whole;
  whole.repeats = options.repeats;
  std::cerr << "whole frame: depth of field, default eye's glare and every perception stage, CPU engine" << std::endl;
  std::cout << "\nThe CPU engine's whole frame: depth of field, the default eye's glare and every perception stage, "
               "beside the sum of its floors measured in the same run (stimuli/whole_frame_benchmark.h).\n\n"
            << format_whole_frame_benchmark(run_whole_frame_benchmark(whole));
  print_load_average("the whole-frame row");
}

// Kakimoto 2007's depth of field over a 1024 x 768 frame with Z on 2 threads, beside its error
// against the per-pixel reference (stimuli/depth_of_field_benchmark.h).
void print_depth_of_field_rows(const BenchArguments& args) {
  const int repeats = args.repeats > 0 ? args.repeats : (args.quick ? 3 : 5);
  std::cerr << "depth of field: 1024 x 768 with Z, " << repeats << " runs and the per-pixel reference" << std::endl;
  std::cout << "Depth of field from the scene's Z (Kakimoto et al. 2007, Eqs. 8-9; docs/DEPTH_OF_FIELD.md): the "
               "layered stage on 2 threads, the fastest of " << repeats << " runs, against the per-pixel scatter "
               "reference. Kakimoto et al. drew ten-sample blur at about 30 fps (33 ms a frame) on a 2007 GPU "
               "(GeForce 7800 GTX).\n\n"
            << format_depth_of_field_benchmark(run_depth_of_field_benchmark(2, repeats));
  print_load_average("the depth-of-field rows");
}

// The analytic models over the whole display and the hybrid against Ritschel
// (stimuli/glare_model_benchmark.h).
void print_analytic_rows(const BenchArguments& args) {
  AnalyticBenchmarkOptions options;
  options.width_px = args.analytic_size[0];
  options.height_px = args.analytic_size[1];
  options.frames = args.frames > 0 ? args.frames : (args.quick ? 3 : 5);
  options.progress = [](const std::string& line) { std::cerr << line << std::endl; };
  std::cout << format_analytic_benchmark(run_analytic_benchmark(options));
  print_load_average("the analytic rows");
  // The two-level convolution sessions use at this size (exact near kernel, far field at a quarter
  // of the resolution) beside the full path and its floor, each frame's error against float64.
  TwoLevelBenchmarkOptions two_level;
  two_level.width_px = options.width_px;
  two_level.height_px = options.height_px;
  two_level.frames = options.frames;
  two_level.progress = options.progress;
  std::cout << "\n" << format_two_level_benchmark(run_two_level_benchmark(two_level));
  print_load_average("the two-level rows");
}

// A session's peak resident size at display size, control and dynamic glare, each in a child
// process (runner/cli/bench_memory.h). Measured before anything else the command does: the child's
// ru_maxrss starts from this process's high-water mark (bench_memory.h says why), so this process
// must not have grown yet.
struct MemoryRows {
  SessionMemoryOptions options;
  std::vector<SessionMemoryRow> rows;
  std::string load_averages;  // at the end of the rows
};

MemoryRows measure_memory_rows(const BenchArguments& args) {
  MemoryRows measured;
  measured.options.width_px = args.memory_size[0];
  measured.options.height_px = args.memory_size[1];
  measured.options.stimulus_frames = args.memory_frames;
  std::cerr << "memory: one trial of a " << measured.options.width_px << " x " << measured.options.height_px
            << " session, control and dynamic glare, each in a child process" << std::endl;
  measured.rows = measure_session_memory(measured.options);
  measured.load_averages = load_average();
  return measured;
}

void print_memory_rows(const MemoryRows& measured) {
  std::cout << format_session_memory(measured.options, measured.rows);
  print_load_average("the memory rows", measured.load_averages);
}

}  // namespace

Action add_bench_command(CLI::App& app) {
  auto args = std::make_shared<BenchArguments>();
  CLI::App* command = app.add_subcommand(
      "bench", "Time the glare stages on the CPU and GL backends beside their errors (a speed-against-error table)");
  command->add_flag("--quick", args->quick, "Grids 256, 512, 1024 and one run per stage (default adds 2048, best of 3)");
  command->add_flag("--no-gl", args->no_gl, "CPU backends only");
  CLI::Option* engine_option = add_choice_option(
      command, "--engine", args->engine,
      "Frame engine to time: cpu (CPU rows only, as --no-gl), gpu (the CPU rows beside the GL rows; with "
      "--perception-only also both engines at the GPU's targets: 1920 x 1080 with hybrid glare, a 1440 x 1600 headset "
      "eye) or auto (gpu on a hardware GPU with OpenGL 4.5, else cpu); default: every backend");
  command->add_option("--grids", args->grids,
                      "Grid sizes N of the glare rows, in aperture pixels (even; powers of two 16..4096 with GL), "
                      "replacing the default 256 512 1024 (2048)")
      ->check(CLI::Range(16, 4096));
  command->add_option("--repeats", args->repeats, "Runs per stage, the fastest kept (default 1 with --quick, else 3)")
      ->check(CLI::Range(1, 100));
  command->add_option("--frames", args->frames,
                      "Whole frames timed per grid and scene kind against the FFTW floor, each at a new eye time, the "
                      "fastest kept (default 5 with --quick, else 10)")
      ->check(CLI::Range(1, 1000));
  command->add_flag("--analytic-only", args->analytic_only,
                    "Only the analytic models (Spencer, CIE) over the whole display and the hybrid and the default (human) eye against Ritschel");
  command->add_flag("--no-analytic", args->no_analytic, "Only the wave-optics (Ritschel) stages");
  command->add_option("--analytic-size", args->analytic_size, "Display of the analytic rows, WIDTH HEIGHT in pixels (default 1920 1080)")
      ->expected(2)
      ->check(CLI::Range(16, 8192));
  command->add_flag("--perception-only", args->perception_only,
                    "Only the perception stages (Luidolt 2020) at 1920 x 1080, CPU and GL, and each frame engine's whole frame");
  command->add_flag("--depth-of-field-only", args->depth_of_field_only,
                    "Only the depth-of-field stage (Kakimoto 2007) on a 1024 x 768 frame with Z");
  command->add_flag("--memory-only", args->memory_only,
                    "Only the memory rows: peak resident size of one trial of a session at --memory-size, control "
                    "and dynamic glare (prepared frames), each in a child process");
  command->add_option("--memory-size", args->memory_size,
                      "Display of the memory rows, WIDTH HEIGHT in pixels (default 1920 1080)")
      ->expected(2)
      ->check(CLI::Range(64, 8192));
  command->add_option("--memory-frames", args->memory_frames, "Stimulus frames of the memory rows' trial (default 30)")
      ->check(CLI::Range(1, 600));
  // The child of a memory row (runner/cli/bench_memory.h): runs one trial of FILE and reports its
  // peak resident size. Not for users, so not listed.
  command->add_option("--memory-child", args->memory_child)->group("");
  return [=]() {
    if (!args->memory_child.empty()) return report_errors([&]() { return run_memory_child(args->memory_child, std::cout); });
    return report_errors([&]() {
      // The engine's one table (stimuli/frame_engine.h) decides whether the GL rows run.
      if (engine_option->count() > 0) {
        const FrameEngineChoice engine = choose_frame_engine(
            args->engine, args->no_gl ? GlContextFactory() : GlContextFactory(gl::compute_context_factory()));
        if (args->no_gl && engine.kind != FrameEngineKind::cpu)
          throw ConfigError({"--engine", 0, 0}, "engine", "--engine gpu and --no-gl exclude each other");
        args->no_gl = engine.kind == FrameEngineKind::cpu;
        std::cout << engine.reason << "\n\n";
      }
      if (args->analytic_only && args->no_analytic)
        throw ConfigError({"--analytic-only", 0, 0}, "analytic-only", "--analytic-only and --no-analytic exclude each other");
      if (static_cast<int>(args->analytic_only) + static_cast<int>(args->perception_only) +
              static_cast<int>(args->depth_of_field_only) + static_cast<int>(args->memory_only) > 1)
        throw ConfigError({"--analytic-only", 0, 0}, "analytic-only",
                          "--analytic-only, --perception-only, --depth-of-field-only and --memory-only exclude each other");
      if (args->memory_only) {
        print_memory_rows(measure_memory_rows(*args));
        return 0;
      }
      if (args->analytic_only) {
        print_analytic_rows(*args);
        return 0;
      }
      if (args->perception_only) {
        print_perception_rows(*args);
        std::cout << "\n";
        print_frame_engine_rows(*args);
        return 0;
      }
      if (args->depth_of_field_only) {
        print_depth_of_field_rows(*args);
        return 0;
      }
      // Bad grids are refused before the memory rows' sessions run.
      for (const int grid : args->grids)
        if (grid % 2 != 0 || (!args->no_gl && !gl::is_power_of_two_fft_length(grid)))
          throw ConfigError({"--grids", 0, 0}, "grids",
                            "grid " + std::to_string(grid) + " is " +
                                (grid % 2 != 0 ? std::string("odd") : std::string("not a GL PSF grid")) +
                                ": even sizes 16 to 4096, powers of two unless --no-gl");
      const MemoryRows memory = measure_memory_rows(*args);
      GlareBenchmarkOptions options;
      options.grid_sizes = !args->grids.empty() ? args->grids
                           : args->quick   ? std::vector<int>{256, 512, 1024}
                                           : std::vector<int>{256, 512, 1024, 2048};
      options.repeats = args->repeats > 0 ? args->repeats : (args->quick ? 1 : 3);
      options.frames = args->frames > 0 ? args->frames : (args->quick ? 5 : 10);
      if (!args->no_gl) options.gl_context = gl::compute_context_factory();
      options.progress = [](const std::string& line) { std::cerr << line << std::endl; };
      const GlareBenchmarkResult result = run_glare_benchmark(options);
      std::cout << "Aperture: " << result.aperture << ".\n";
      if (!result.renderer.empty()) std::cout << "OpenGL renderer: " << result.renderer << ".\n";
      std::ifstream cpuinfo("/proc/cpuinfo");
      for (std::string line; std::getline(cpuinfo, line);)
        if (line.rfind("model name", 0) == 0) {
          std::cout << "CPU: " << line.substr(line.find(':') + 2) << ".\n";
          break;
        }
      print_load_average("the run");
      std::cout << "Errors are relative L2: against the CPU double path at the same N, and the monochromatic PSF "
                   "against the CPU double PSF of the 2N grid (central N x N).\n\n"
                << format_glare_benchmark_table(result);
      if (const std::string gl_frames = format_gl_frame_table(result); !gl_frames.empty())
        std::cout << "\nGL frame: the PSF stages' wall times (each ended by glFinish), the convolution's GPU time alone "
                     "(timestamp queries from the image's upload to the result's read-back) beside its wall time (with "
                     "the host's pixel checks and bright-pixel split), and the frame both ways. Each call has a new PSF; a new "
                     "scene checks, splits, uploads and transforms its image too, a static scene (a fixed stimulus under "
                     "dynamic glare) keeps the image's spectrum.\n\n"
                  << gl_frames;
      std::cout << "\nWhole dynamic frame of the planned cpu float32 path (aperture, PSF, spectral PSF at the display "
                   "scale, RGB convolution of the N x 3N/4 frame; each frame at a new eye time, the fastest kept) "
                   "against the FFTW floor (FFTW float, plans made once, the same threads: one N x N complex FFT and "
                   "nine padded real transforms, 3 forward image, 3 forward PSF, 3 inverse). A static scene keeps its "
                   "spectrum; a new scene transforms its R, G, B again.\n\n"
                << format_glare_frame_table(result);
      if (!args->no_gl) std::cout << "\n" << create_glare_backend(GlareBackendRequest::automatic, {.gl_context = gl::compute_context_factory()}).reason << "\n";
      if (!args->no_analytic) {
        std::cout << "\n";
        print_analytic_rows(*args);
      }
      std::cout << "\n";
      print_perception_rows(*args);
      std::cout << "\n";
      print_frame_engine_rows(*args);
      std::cout << "\n";
      print_depth_of_field_rows(*args);
      std::cout << "\n";
      print_memory_rows(memory);
      return 0;
    });
  };
}

}  // namespace glarelab::cli
