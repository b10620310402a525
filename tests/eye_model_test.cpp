// The assembled eye: determinism, modes, seeds, parameter validation and the eye-trace command.
#include <gtest/gtest.h>

#include <chrono>
#include <cstring>
#include <fstream>
#include <sstream>

#include "cli_process.h"
#include "glare/eye/eye_model.h"
#include "core/errors.h"
#include "scratch_dir.h"

namespace glarelab {
namespace {

// Bit-for-bit equality of two apertures.
void expect_identical(const ApertureGeometry& a, const ApertureGeometry& b) {
  EXPECT_EQ(std::memcmp(&a.pupil_diameter_mm, &b.pupil_diameter_mm, sizeof(double)), 0);
  EXPECT_EQ(std::memcmp(&a.defocus_dioptres, &b.defocus_dioptres, sizeof(double)), 0);
  EXPECT_EQ(a.glare_enabled, b.glare_enabled);
  ASSERT_EQ(a.discs.size(), b.discs.size());
  ASSERT_EQ(a.lines.size(), b.lines.size());
  ASSERT_EQ(a.polygons.size(), b.polygons.size());
  EXPECT_EQ(std::memcmp(a.discs.data(), b.discs.data(), a.discs.size() * sizeof(ApertureDisc)), 0);
  EXPECT_EQ(std::memcmp(a.lines.data(), b.lines.data(), a.lines.size() * sizeof(ApertureLine)), 0);
  for (std::size_t k = 0; k < a.polygons.size(); ++k) {
    EXPECT_EQ(a.polygons[k].vertices_mm, b.polygons[k].vertices_mm);
    EXPECT_EQ(a.polygons[k].transmittance, b.polygons[k].transmittance);
  }
}

bool differs(const ApertureGeometry& a, const ApertureGeometry& b) {
  if (a.pupil_diameter_mm != b.pupil_diameter_mm || a.discs.size() != b.discs.size()) return true;
  for (std::size_t k = 0; k < a.discs.size(); ++k)
    if (a.discs[k].centre_x_mm != b.discs[k].centre_x_mm) return true;
  return false;
}

TEST(EyeModel, GeometryAtTIsBitIdenticalFreshOrAfterEarlierFrames) {
  EyeParameters p;
  p.initial_field_luminance_cd_m2 = 0.5;  // large pupil: gratings, lids and lashes all in play
  const EyeModel warmed(p, 17);
  for (int frame = 0; frame < 60 * 12; ++frame) (void)warmed.geometry_at(frame / 60.0);
  for (const double t : {12.3456, 3.7, 0.0}) {
    const EyeModel fresh(p, 17);
    expect_identical(fresh.geometry_at(t), warmed.geometry_at(t));
  }
}

TEST(EyeModel, StaticEyeIsFrozenAtItsTime) {
  EyeParameters p;
  p.mode = GlareMode::static_eye;
  p.static_time_s = 2.5;
  const EyeModel frozen(p, 5);
  expect_identical(frozen.geometry_at(0.0), frozen.geometry_at(10.0));
  EyeParameters dynamic_parameters = p;
  dynamic_parameters.mode = GlareMode::dynamic;
  const EyeModel moving(dynamic_parameters, 5);
  expect_identical(frozen.geometry_at(7.0), moving.geometry_at(2.5));
  EXPECT_TRUE(differs(moving.geometry_at(0.0), moving.geometry_at(10.0))) << "the dynamic eye must move";
}

TEST(EyeModel, ControlHasNoGlare) {
  EyeParameters p;
  p.mode = GlareMode::control;
  const EyeModel control(p, 5);
  const ApertureGeometry g = control.geometry_at(3.0);
  EXPECT_FALSE(g.glare_enabled);
  EXPECT_TRUE(g.discs.empty());
  EXPECT_TRUE(g.lines.empty());
  EXPECT_TRUE(g.polygons.empty());
  EXPECT_EQ(g.defocus_dioptres, 0.0);
  EXPECT_EQ(g.pupil_diameter_mm, control.state_at(3.0).pupil_diameter_mm);
  p.mode = GlareMode::dynamic;
  EXPECT_TRUE(EyeModel(p, 5).geometry_at(3.0).glare_enabled);
}

TEST(EyeModel, SameSeedSameEyeDifferentSeedDifferentEye) {
  const EyeParameters p;
  expect_identical(EyeModel(p, 99).geometry_at(4.0), EyeModel(p, 99).geometry_at(4.0));
  EXPECT_TRUE(differs(EyeModel(p, 99).geometry_at(4.0), EyeModel(p, 100).geometry_at(4.0)));
}

TEST(EyeModel, ApertureHoldsEveryComponent) {
  EyeParameters p;
  p.initial_field_luminance_cd_m2 = 0.01;
  const EyeModel eye(p, 3);
  const ApertureGeometry g = eye.geometry_at(1.0);
  EXPECT_EQ(g.discs.size(), static_cast<std::size_t>(p.cornea_particle_count + p.lens_particle_count +
                                                     p.vitreous_particle_count + p.retina_particle_count));
  EXPECT_EQ(g.polygons.size(), 2u);
  EXPECT_GT(g.pupil_diameter_mm, 5.0);
  EXPECT_LE(g.pupil_diameter_mm, 9.0);
}

TEST(EyeModel, InvalidParametersNameTheKey) {
  EyeParameters p;
  p.lens_particle_count = -1;
  try {
    EyeModel eye(p, 1);
    FAIL() << "expected a ConfigError";
  } catch (const ConfigError& error) {
    EXPECT_EQ(error.key(), "lens_particle_count");
  }
  p = EyeParameters{};
  p.vitreous_time_step_s = 0.1;
  EXPECT_THROW(validate(p), ConfigError);
  p = EyeParameters{};
  p.pupil_min_diameter_mm = 9.5;
  EXPECT_THROW(validate(p), ConfigError);
  EXPECT_THROW(parse_glare_mode("frozen"), ConfigError);
  EXPECT_EQ(parse_glare_mode("static"), GlareMode::static_eye);
  EXPECT_NO_THROW(validate(EyeParameters{}));
}

TEST(EyeModel, GeometryTimingPerFrame) {
  // Not an assertion on speed (benchmarks do that): prints the cost of one frame for the report.
  EyeParameters p;
  p.initial_field_luminance_cd_m2 = 0.5;
  const EyeModel eye(p, 1);
  const auto start = std::chrono::steady_clock::now();
  std::size_t primitives = 0;
  for (int frame = 0; frame < 600; ++frame) primitives += eye.geometry_at(frame / 60.0).discs.size();
  const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  std::printf("geometry_at: %.3f ms per frame (sequential 60 Hz frames), %zu discs per frame\n", ms / 600.0,
              primitives / 600);
  const auto fresh_start = std::chrono::steady_clock::now();
  const EyeModel cold(p, 1);
  (void)cold.geometry_at(600.0);
  std::printf("geometry_at(600 s) on a fresh model (integrating the vitreous from 0): %.3f ms\n",
              std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - fresh_start).count());
  EXPECT_GT(primitives, 0u);
}

TEST(EyeTraceCommand, WritesTheTraceAsCsv) {
  test::ScratchDir dir;
  const auto out = dir.path() / "trace.csv";
  const auto result = test::run_glarelab({"eye-trace", "--duration-s", "2", "--rate-hz", "10",
                                          "--field-luminance-cd-m2", "100", "--seed", "1", "--out", out.string()},
                                         dir.path());
  ASSERT_EQ(result.exit_code, 0) << result.output;
  std::ifstream in(out);
  std::string header;
  std::getline(in, header);
  EXPECT_EQ(header.rfind("time_s,field_luminance_cd_m2,mean_pupil_diameter_mm,pupil_diameter_mm,accommodation_dioptres,", 0), 0u)
      << header;
  EXPECT_NE(header.find("vitreous_angle_deg"), std::string::npos);
  EXPECT_NE(header.find("blink_closure"), std::string::npos);
  std::string line;
  int rows = 0;
  while (std::getline(in, line)) {
    std::istringstream fields(line);
    std::string time, field, mean;
    std::getline(fields, time, ',');
    std::getline(fields, field, ',');
    std::getline(fields, mean, ',');
    EXPECT_NEAR(std::stod(time), rows * 0.1, 1e-9);
    EXPECT_NEAR(std::stod(mean), moon_spencer_pupil_diameter_mm(100.0), 1e-6);  // Eq. 2 at 100 cd/m2
    ++rows;
  }
  EXPECT_EQ(rows, 21);
  const auto bad = test::run_glarelab({"eye-trace", "--mode", "frozen", "--out", out.string()}, dir.path());
  EXPECT_EQ(bad.exit_code, 2) << bad.output;
  EXPECT_NE(bad.output.find("frozen"), std::string::npos);
}

}  // namespace
}  // namespace glarelab
