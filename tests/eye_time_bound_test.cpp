// Times given to the eye model cost no time in proportion to their value: the vitreous forgets its
// past (glare/eye/vitreous_model.h), and every entry point that takes a time refuses one past 24 h
// (kMaxEyeModelTime_s) with exit 2, naming the flag or the file, line, column and key, before it
// writes anything; a time at the bound still works.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <vector>

#include "cli_process.h"
#include "core/errors.h"
#include "core/exr_io.h"
#include "glare/eye/eye_model.h"
#include "glare/eye/vitreous_model.h"
#include "scratch_dir.h"

namespace glarelab {
namespace {

double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

struct TimedRun {
  test::RunOutput run;
  double seconds = 0.0;
};

TimedRun timed_run(const std::vector<std::string>& arguments, const std::filesystem::path& dir) {
  const auto start = std::chrono::steady_clock::now();
  TimedRun result{test::run_glarelab(arguments, dir), 0.0};
  result.seconds = seconds_since(start);
  return result;
}

void expect_refused(const TimedRun& result, const std::vector<std::string>& words, const std::filesystem::path& out) {
  EXPECT_EQ(result.run.exit_code, 2) << result.run.output;
  for (const std::string& word : words) EXPECT_NE(result.run.output.find(word), std::string::npos) << word << "\n" << result.run.output;
  EXPECT_FALSE(std::filesystem::exists(out)) << out;
  EXPECT_LT(result.seconds, 5.0) << "a refusal must not wait for the model";
}

TEST(EyeTimeBound, VitreousForgetsItsPastWithinTheStatedBound) {
  const EyeParameters p;
  const VitreousDynamics dynamics(p, 5);
  // Defaults: slow root 1.2 / s, ||A^M|| <= 2^-60 after ~35 s; epochs of four windows.
  ASSERT_GT(dynamics.forgetting_window_s(), 20.0);
  ASSERT_LT(dynamics.forgetting_window_s(), 60.0);
  EXPECT_DOUBLE_EQ(dynamics.epoch_s(), 4.0 * dynamics.forgetting_window_s());
  // Epoch 0 is the integration from t = 0, bit for bit.
  for (const double t : {0.25, 17.3, dynamics.epoch_s() - 0.3}) {
    const VitreousState windowed = dynamics.state_at(t), full = dynamics.state_integrated_from_zero(t);
    EXPECT_EQ(windowed.angle_rad, full.angle_rad) << t;
    EXPECT_EQ(windowed.angular_velocity_rad_s, full.angular_velocity_rad_s) << t;
  }
  // Later epochs: the integration from 0 plus at most 2^-60 of the state at the window's start,
  // plus rounding of the size the integration from 0 carries itself.
  double worst_rad = 0.0;
  for (const double t : {dynamics.epoch_s() + 0.7, 2.0 * dynamics.epoch_s() + 12.3, 1000.4, 3001.0}) {
    const VitreousState windowed = dynamics.state_at(t), full = dynamics.state_integrated_from_zero(t);
    EXPECT_NEAR(windowed.angle_rad, full.angle_rad, 1e-14) << t;
    EXPECT_NEAR(windowed.angular_velocity_rad_s, full.angular_velocity_rad_s, 1e-14) << t;
    worst_rad = std::max(worst_rad, std::abs(windowed.angle_rad - full.angle_rad));
  }
  std::printf("vitreous: window %.1f s, epoch %.1f s; windowed against integrated from 0: %.2e rad at most\n",
              dynamics.forgetting_window_s(), dynamics.epoch_s(), worst_rad);

  // The cost does not grow with t: 24 h on a fresh model (integrating from 0 took seconds), and the
  // same answer on a model that was asked about other times first.
  const auto start = std::chrono::steady_clock::now();
  const VitreousState late = VitreousDynamics(p, 5).state_at(kMaxEyeModelTime_s);
  const double fresh_s = seconds_since(start);
  EXPECT_LT(fresh_s, 1.0);
  const VitreousDynamics warmed(p, 5);
  for (int k = 0; k < 50; ++k) (void)warmed.state_at(kMaxEyeModelTime_s - 500.0 + 7.3 * k);
  EXPECT_EQ(warmed.state_at(kMaxEyeModelTime_s).angle_rad, late.angle_rad);
  EXPECT_TRUE(std::isfinite(late.angle_rad));
  std::printf("vitreous: state at 24 h on a fresh model in %.1f ms\n", fresh_s * 1e3);
}

TEST(EyeTimeBound, EyeModelAnswersUpToTheBoundAndRefusesPastIt) {
  EyeParameters p;
  const EyeModel eye(p, 3);
  EXPECT_NO_THROW((void)eye.geometry_at(kMaxEyeModelTime_s));
  EXPECT_THROW((void)eye.state_at(std::nextafter(kMaxEyeModelTime_s, 1e300)), std::invalid_argument);
  p.static_time_s = kMaxEyeModelTime_s;
  EXPECT_NO_THROW(validate(p));
  p.static_time_s = 1e9;
  try {
    validate(p);
    ADD_FAILURE() << "static_time_s = 1e9 accepted";
  } catch (const ConfigError& error) {
    EXPECT_EQ(error.key(), "static_time_s");
    EXPECT_NE(std::string(error.what()).find("at most 86400 s (24 h)"), std::string::npos) << error.what();
  }
}

TEST(EyeTimeBound, PsfTimeIsRefusedPastTheBoundAndWorksAtIt) {
  test::ScratchDir dir;
  const auto out = dir.path() / "psf.exr";
  const std::vector<std::string> eye = {"psf", "--model", "ritschel", "--mode", "dynamic", "--grid", "64", "--out", out.string(), "--time-s"};
  auto with_time = [&](const std::string& time) {
    std::vector<std::string> arguments = eye;
    arguments.push_back(time);
    return arguments;
  };
  expect_refused(timed_run(with_time("1e9"), dir.path()), {"--time-s", "at most 86400 s (24 h)", "1e9"}, out);
  expect_refused(timed_run(with_time("nan"), dir.path()), {"--time-s", "finite"}, out);
  expect_refused(timed_run(with_time("inf"), dir.path()), {"--time-s", "finite"}, out);
  const TimedRun at_bound = timed_run(with_time("86400"), dir.path());
  ASSERT_EQ(at_bound.run.exit_code, 0) << at_bound.run.output;
  EXPECT_TRUE(std::filesystem::exists(out));
  EXPECT_LT(at_bound.seconds, 10.0);
  std::printf("psf --time-s 86400: %.2f s\n", at_bound.seconds);
}

TEST(EyeTimeBound, EyeTraceDurationAndStaticTimeAreRefusedPastTheBound) {
  test::ScratchDir dir;
  const auto out = dir.path() / "trace.csv";
  expect_refused(timed_run({"eye-trace", "--duration-s", "1e9", "--rate-hz", "0.001", "--out", out.string()}, dir.path()),
                 {"--duration-s", "at most 86400 s (24 h)"}, out);
  expect_refused(timed_run({"eye-trace", "--mode", "static", "--static-time-s", "1e12", "--out", out.string()}, dir.path()),
                 {"--static-time-s", "at most 86400 s (24 h)"}, out);
  // At the bound: a day at one sample per hour (25 rows), and a static eye frozen at 24 h.
  const TimedRun day = timed_run({"eye-trace", "--duration-s", "86400", "--rate-hz", "0.000277777777777778", "--out",
                                  out.string()},
                                 dir.path());
  ASSERT_EQ(day.run.exit_code, 0) << day.run.output;
  EXPECT_NE(day.run.output.find("25 samples"), std::string::npos) << day.run.output;
  EXPECT_LT(day.seconds, 10.0);
  const TimedRun frozen = timed_run(
      {"eye-trace", "--mode", "static", "--static-time-s", "86400", "--duration-s", "1", "--out", out.string()}, dir.path());
  ASSERT_EQ(frozen.run.exit_code, 0) << frozen.run.output;
  EXPECT_LT(frozen.seconds, 10.0);
  std::printf("eye-trace over 24 h: %.2f s; static eye at 24 h: %.2f s\n", day.seconds, frozen.seconds);
}

// A 32 x 32 scene with a bright centre, and an experiment whose conditions show it with static glare.
std::string write_static_experiment(const test::ScratchDir& dir, const std::string& static_time) {
  ImageRGBA scene(32, 32, 0.0f);
  for (int y = 14; y < 18; ++y)
    for (int x = 14; x < 18; ++x)
      for (int c = 0; c < 3; ++c) scene.pixel(x, y)[c] = 200.0f;
  write_exr((dir.path() / "lamp.exr").string(), scene);
  // static_time_s is on line 20, its value from column 17.
  return dir.write("experiment.toml", R"([experiment]
name = "static-time"
seed = 42

[display]
width_px = 128
height_px = 64
peak_luminance_cd_m2 = 250.0

[scenes]
lamp = { file = "lamp.exr" }

[procedure]
type = "forced_choice"
stimulus_frames = 2

[glare]
grid_px = 64
wavelength_samples = 4
static_time_s = )" + static_time + R"(

[[conditions.rows]]
name = "frozen"
scene_a = "lamp"
scene_b = "lamp"
glare = "static"
)");
}

TEST(EyeTimeBound, ExperimentStaticTimeIsRefusedPastTheBoundWithItsPlace) {
  test::ScratchDir dir;
  const std::string experiment = write_static_experiment(dir, "1e9");
  const auto out = dir.path() / "frame.exr";
  expect_refused(timed_run({"validate", experiment}, dir.path()),
                 {"experiment.toml:20:17", "static_time_s", "must be at most 86400 s (24 h), found 1e+09"}, out);
  expect_refused(timed_run({"render", experiment, "--condition", "frozen", "--out", out.string()}, dir.path()),
                 {"experiment.toml:20:17", "static_time_s", "at most 86400 s (24 h)"}, out);
  const std::string at_bound = write_static_experiment(dir, "86400.0");
  const TimedRun rendered = timed_run({"render", at_bound, "--condition", "frozen", "--out", out.string()}, dir.path());
  ASSERT_EQ(rendered.run.exit_code, 0) << rendered.run.output;
  EXPECT_TRUE(std::filesystem::exists(out));
  EXPECT_LT(rendered.seconds, 10.0);
  std::printf("render with static_time_s = 86400: %.2f s\n", rendered.seconds);
}

TEST(EyeTimeBound, RenderTimeIsRefusedPastTheBoundAndWorksAtIt) {
  test::ScratchDir dir;
  std::string experiment = write_static_experiment(dir, "0.5");
  const auto out = dir.path() / "frame.exr";
  const std::vector<std::string> render = {"render", experiment, "--condition", "frozen", "--glare", "dynamic",
                                           "--out", out.string(), "--time"};
  auto at = [&](const std::string& time) {
    std::vector<std::string> arguments = render;
    arguments.push_back(time);
    return arguments;
  };
  expect_refused(timed_run(at("1e7"), dir.path()), {"--time", "at most 86400 s (24 h)", "1e7"}, out);
  expect_refused(timed_run(at("nan"), dir.path()), {"--time", "finite"}, out);
  expect_refused(timed_run(at("-1"), dir.path()), {"--time", ">= 0"}, out);
  const TimedRun at_bound = timed_run(at("86400"), dir.path());
  ASSERT_EQ(at_bound.run.exit_code, 0) << at_bound.run.output;
  EXPECT_TRUE(std::filesystem::exists(out));
  EXPECT_LT(at_bound.seconds, 10.0);
  std::printf("render --time 86400: %.2f s\n", at_bound.seconds);
}

}  // namespace
}  // namespace glarelab
