// Choosing the frame engine (core/frame_engine_request.h, stimuli/frame_engine.h): `[display]
// engine` in the experiment file and `--engine` on run, render and bench, the flag winning; each
// value changes what makes the frames, and the session's `engine` event says which engine ran with
// each stage's backend. Bad values stop the run with exit 2 at file:line:column or at the flag.
#include <gtest/gtest.h>

#include <algorithm>
#include <string>
#include <vector>

#include "cli_process.h"
#include "experiment_error.h"
#include "protocols/experiment.h"
#include "scratch_dir.h"
#include "session_events.h"
#include "stimuli/frame_engine.h"

namespace glarelab {
namespace {

// The demo's lines 1-24 end with [display] height_px on line 24; `engine` goes on line 25.
std::string demo_with_display_line(const std::string& line) {
  const std::string demo = test::read_bytes(std::string(GLARELAB_SOURCE_DIR) + "/examples/demo.toml");
  const std::string anchor = "height_px = 512\n";
  std::string text = demo;
  text.insert(text.find(anchor) + anchor.size(), line + "\n");
  return text;
}

TEST(EngineChoice, TheDisplayKeyIsReadWrittenBackAndCheckedAtItsValue) {
  const std::string examples = std::string(GLARELAB_SOURCE_DIR) + "/examples";
  for (const auto& [word, request] : {std::pair{"cpu", FrameEngineRequest::cpu}, std::pair{"gpu", FrameEngineRequest::gpu},
                                      std::pair{"auto", FrameEngineRequest::automatic}}) {
    const Experiment experiment =
        parse_experiment_text(demo_with_display_line(std::string("engine = \"") + word + "\""), "demo.toml", examples);
    EXPECT_EQ(experiment.engine, request) << word;
    // The stored configuration reads back to the same request.
    const Experiment reread = parse_experiment_text(resolved_config_toml(experiment), "<stored config>", "/");
    EXPECT_EQ(reread.engine, request) << word;
  }
  // Without the key: auto.
  EXPECT_EQ(load_experiment(examples + "/demo.toml").engine, FrameEngineRequest::automatic);

  const test::ScratchDir dir;
  const std::string text = demo_with_display_line("engine = \"cuda\"");
  const std::string path = dir.write("demo.toml", text);
  // The value's line and column, counted here from the text.
  const std::size_t at = text.find("engine = \"cuda\"");
  const int line = 1 + static_cast<int>(std::count(text.begin(), text.begin() + static_cast<std::ptrdiff_t>(at), '\n'));
  EXPECT_EQ(line, 25);
  const std::string error = test::experiment_error(path);
  EXPECT_NE(error.find(path + ":25:10: key 'display.engine': unknown value 'cuda' (supported: 'auto', 'cpu', 'gpu')"),
            std::string::npos)
      << error;
}

// A bad flag is refused before anything runs, naming the flag and the words it takes (exit 2).
TEST(EngineChoice, ABadFlagExitsTwoNamingIt) {
  const test::ScratchDir scratch;
  const std::string demo = std::string(GLARELAB_SOURCE_DIR) + "/examples/demo.toml";
  const auto db = scratch.path() / "refused.db";
  for (const std::vector<std::string>& command :
       {std::vector<std::string>{"run", demo, "--display", "offscreen", "--observer", "simulated", "--db", db.string(),
                                 "--engine", "cuda"},
        std::vector<std::string>{"render", demo, "--condition", "control_1.000", "--out",
                                 (scratch.path() / "frame.exr").string(), "--engine", "cuda"},
        std::vector<std::string>{"bench", "--engine", "cuda"}}) {
    const test::RunOutput output = test::run_glarelab(command, scratch.path());
    EXPECT_EQ(output.exit_code, 2) << command.front() << ": " << output.output;
    EXPECT_NE(output.output.find("--engine"), std::string::npos) << output.output;
    EXPECT_NE(output.output.find("unknown value 'cuda' (supported: 'auto', 'cpu', 'gpu')"), std::string::npos)
        << output.output;
  }
  EXPECT_FALSE(std::filesystem::exists(db));
}

// The one `engine` event of a short session of the small dynamic demo (`display_line` added to
// its [display] table), run with `flags`.
std::string engine_event(const test::ScratchDir& scratch, const std::string& name, const std::string& display_line,
                         const std::vector<std::string>& flags) {
  const auto dir = scratch.path() / name;
  std::filesystem::create_directories(dir);
  const auto file = test::small_dynamic_demo(dir, "");
  if (!display_line.empty()) {
    std::string text = test::read_bytes(file.string());
    text.insert(text.find("height_px = 256\n") + 16, display_line + "\n");
    test::write_bytes(file.string(), text);
  }
  const auto db = dir / "session.db";
  std::vector<std::string> command = {"run",  file.string(), "--display",    "offscreen", "--observer",
                                      "simulated", "--db",   db.string(), "--stop-after", "1"};
  command.insert(command.end(), flags.begin(), flags.end());
  const test::RunOutput output = test::run_glarelab(command, dir);
  EXPECT_EQ(output.exit_code, 0) << output.output;
  const std::vector<std::string> events = test::session_event_messages(db.string(), "engine");
  EXPECT_EQ(events.size(), 1u) << output.output;
  return events.empty() ? std::string() : events.front();
}

// Each value changes what runs: "cpu" the CPU engine on the planned float32 glare, "gpu" the GL
// engine on the GL glare backend (here Mesa's llvmpipe where there is no GPU), "auto" on a
// software renderer the CPU engine. The flag beats [display] engine either way.
TEST(EngineChoice, EachValueChangesWhatRunsAndTheFlagBeatsTheKey) {
  const test::ScratchDir scratch;
  const std::string cpu = engine_event(scratch, "cpu", "", {"--engine", "cpu"});
  EXPECT_NE(cpu.find("asked for cpu"), std::string::npos) << cpu;
  EXPECT_NE(cpu.find("frame engine cpu: glare backend cpu float32 planned"), std::string::npos) << cpu;
  EXPECT_NE(cpu.find("glare cpu float32 planned; perception stages cpu float32"), std::string::npos) << cpu;
  EXPECT_NE(cpu.find("read back: nothing"), std::string::npos) << cpu;

  const std::string gpu = engine_event(scratch, "gpu", "", {"--engine", "gpu"});
  if (gpu.find("no OpenGL 4.5") != std::string::npos) GTEST_SKIP() << "no OpenGL 4.5 context here: " << gpu;
  EXPECT_NE(gpu.find("asked for gpu"), std::string::npos) << gpu;
  EXPECT_NE(gpu.find("frame engine gl: glare backend gl"), std::string::npos) << gpu;
  EXPECT_NE(gpu.find("spectacle warp cpu; depth of field cpu; glare gl; perception stages gl"), std::string::npos) << gpu;
  EXPECT_NE(gpu.find("read back: in a session none of the frame"), std::string::npos) << gpu;

  // The file asks for gpu, the flag for cpu: cpu runs. And the other way round.
  const std::string flag_cpu = engine_event(scratch, "flag_cpu", "engine = \"gpu\"", {"--engine", "cpu"});
  EXPECT_NE(flag_cpu.find("frame engine cpu: glare backend cpu float32 planned"), std::string::npos) << flag_cpu;
  const std::string flag_gpu = engine_event(scratch, "flag_gpu", "engine = \"cpu\"", {"--engine", "gpu"});
  EXPECT_NE(flag_gpu.find("frame engine gl: glare backend gl"), std::string::npos) << flag_gpu;
  // The key alone decides without the flag.
  const std::string key_gpu = engine_event(scratch, "key_gpu", "engine = \"gpu\"", {});
  EXPECT_NE(key_gpu.find("asked for gpu"), std::string::npos) << key_gpu;
  EXPECT_NE(key_gpu.find("frame engine gl: glare backend gl"), std::string::npos) << key_gpu;

  // auto: the renderer here decides. On a software rasteriser the glare backend's reason says so
  // and the CPU engine runs; on a hardware GPU the GL engine.
  const std::string automatic = engine_event(scratch, "auto", "", {"--engine", "auto"});
  EXPECT_NE(automatic.find("asked for auto"), std::string::npos) << automatic;
  if (automatic.find("a software rasteriser") != std::string::npos)
    EXPECT_NE(automatic.find("frame engine cpu: glare backend cpu float32 planned"), std::string::npos) << automatic;
  else
    EXPECT_NE(automatic.find("frame engine gl: glare backend gl"), std::string::npos) << automatic;
}

// The choice without a frame (bench): named requests take their engine, auto with no GL takes the CPU.
TEST(EngineChoice, ChooseFrameEngineAnswersFromTheTable) {
  EXPECT_EQ(choose_frame_engine(FrameEngineRequest::cpu, {}).kind, FrameEngineKind::cpu);
  EXPECT_EQ(choose_frame_engine(FrameEngineRequest::gpu, {}).kind, FrameEngineKind::gl);
  const FrameEngineChoice automatic = choose_frame_engine(FrameEngineRequest::automatic, {});
  EXPECT_EQ(automatic.kind, FrameEngineKind::cpu);
  EXPECT_NE(automatic.reason.find("no OpenGL 4.5 context"), std::string::npos) << automatic.reason;
}

}  // namespace
}  // namespace glarelab
