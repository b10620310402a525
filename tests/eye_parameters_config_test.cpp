// [glare.eye]: every key of the eye model read from the experiment file changes what it should in
// the eye model (asserted on its state, its aperture or its PSF against the closed form of the
// model's equations, never just on the stored value), reaches the session's glare stage, is written
// back in the resolved experiment, and bad values stop `run` and `validate` with exit 2 at
// file:line:column naming the key, before anything is written.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <map>
#include <numbers>
#include <set>
#include <string>
#include <vector>

#include "cli_process.h"
#include "glare/cpu/psf.h"
#include "glare/eye/aperture_raster.h"
#include "glare/eye/cornea_retina.h"
#include "glare/eye/eye_model.h"
#include "glare/eye/pupil_model.h"
#include "protocols/experiment.h"
#include "protocols/eye_parameters_config.h"
#include "stimuli/glare_stage.h"

namespace glarelab {
namespace {

using test::ScratchDir;

constexpr std::uint64_t kSeed = 11;

// An experiment whose [glare.eye] table holds `eye_lines` (line 3 onwards).
std::string experiment_with_eye(const std::string& eye_lines) {
  return "[glare]\n[glare.eye]\n" + eye_lines +
         "\n[experiment]\nname = \"p\"\n[scenes]\na = { file = \"a.exr\" }\n[procedure]\ntype = \"forced_choice\"\n"
         "[[conditions.rows]]\nname = \"one\"\nscene_a = \"a\"\nscene_b = \"a\"\n";
}

EyeParameters eye_read(const std::string& eye_lines) {
  return parse_experiment_text(experiment_with_eye(eye_lines), "p.toml", "/tmp").glare.eye;
}

std::string refusal(const std::string& eye_lines) {
  try {
    parse_experiment_text(experiment_with_eye(eye_lines), "p.toml", "/tmp");
  } catch (const ConfigError& error) {
    return error.what();
  }
  return "no error";
}

std::size_t count_discs(const ApertureGeometry& geometry, ApertureComponent component) {
  return static_cast<std::size_t>(std::count_if(geometry.discs.begin(), geometry.discs.end(),
                                                [&](const ApertureDisc& d) { return d.component == component; }));
}

std::vector<ApertureLine> lines_of(const ApertureGeometry& geometry, ApertureComponent component) {
  std::vector<ApertureLine> out;
  for (const ApertureLine& line : geometry.lines)
    if (line.component == component) out.push_back(line);
  return out;
}

// The lids alone at `closure`, rasterised over a 9.8 mm pupil: the top and bottom of the opening
// (mm) in the pixel column nearest x_mm.
struct Opening {
  double top_mm = 0.0, bottom_mm = 0.0;
};
Opening lid_opening(const EyeModel& eye, double closure, double x_mm) {
  ApertureGeometry lids;
  lids.pupil_diameter_mm = 9.8;
  eye.eyelids().append_occluders(closure, lids);
  lids.lines.clear();  // the lashes
  ApertureRasterOptions options;
  options.grid_px = 512;
  options.aperture_width_mm = 10.0;
  const ApertureGrid grid = rasterise_aperture(lids, options);
  const double dx = grid.pixel_mm();
  const int column = static_cast<int>(std::lround(x_mm / dx)) + grid.grid_px / 2;
  Opening opening{-1e9, 1e9};
  for (int row = 0; row < grid.grid_px; ++row) {
    if (grid.transmittance[static_cast<std::size_t>(row) * grid.grid_px + column] < 0.5) continue;
    const double y = (grid.grid_px / 2 - row) * dx;
    opening.top_mm = std::max(opening.top_mm, y);
    opening.bottom_mm = std::min(opening.bottom_mm, y);
  }
  return opening;
}

// The upper and lower margin centres at closure c (glare/eye/eyelids.h: linear from the open height
// to the meeting height, the lids overlapping by 0.2 mm when closed).
double upper_margin(const EyeParameters& p, double c) {
  return p.upper_lid_open_margin_mm + c * (p.lid_meeting_height_mm - 0.1 - p.upper_lid_open_margin_mm);
}
double lower_margin(const EyeParameters& p, double c) {
  return p.lower_lid_open_margin_mm + c * (p.lid_meeting_height_mm + 0.1 - p.lower_lid_open_margin_mm);
}

// The vitreous angle after one saccade of impulse J at t = 0, its force J / tau exp(-t / tau), in
// closed form: theta'' + 2 zeta w0 theta' + w0^2 theta = f (overdamped, roots s1 < s2), the impulse
// response (e^{-s1 t} - e^{-s2 t}) / (s2 - s1) convolved with f.
double exact_vitreous_angle(const EyeParameters& p, double impulse, double t) {
  const double w0 = 2.0 * std::numbers::pi * p.vitreous_natural_frequency_hz, zeta = p.vitreous_damping_ratio;
  const double root = std::sqrt(zeta * zeta - 1.0);
  const double s1 = w0 * (zeta - root), s2 = w0 * (zeta + root), rate = 1.0 / p.saccade_force_decay_s;
  const double part1 = (std::exp(-rate * t) - std::exp(-s1 * t)) / (s1 - rate);
  const double part2 = (std::exp(-rate * t) - std::exp(-s2 * t)) / (s2 - rate);
  return impulse * rate / (s2 - s1) * (part1 - part2);
}

// Largest |integrated - closed form| over the first 2 s, relative to the largest angle.
double vitreous_error(const EyeParameters& p) {
  const VitreousDynamics dynamics(p, std::vector<Saccade>{{0.0, 0.1}});
  double worst = 0.0, largest = 0.0;
  for (double t = 0.01; t < 2.0; t += 0.01) {
    const double exact = exact_vitreous_angle(p, 0.1, t);
    largest = std::max(largest, std::abs(exact));
    worst = std::max(worst, std::abs(dynamics.state_at(t).angle_rad - exact));
  }
  return worst / largest;
}

// Energy of the PSF outside a radius of 12 pixels (the Airy core of a 7 mm pupil is 3.5 px across on
// a 10 mm grid; 512 px of 4 x 4 sub-samples resolve the 5-20 um particles): the light they scatter.
double wing_energy(const ApertureGeometry& geometry) {
  MonochromaticPsfOptions options;
  options.raster.grid_px = 512;
  options.raster.supersampling = 4;
  const Psf psf = compute_monochromatic_psf(geometry, options).psf;
  double wing = 0.0;
  for (int y = 0; y < psf.size_px; ++y)
    for (int x = 0; x < psf.size_px; ++x)
      if (std::hypot(x - psf.size_px / 2, y - psf.size_px / 2) > 12.0) wing += psf.at(0, x, y);
  return wing;
}

// The lens particles alone in a 7 mm pupil, in focus.
ApertureGeometry lens_particles_only(const EyeModel& eye) {
  ApertureGeometry geometry;
  geometry.pupil_diameter_mm = 7.0;
  eye.lens().append_particles(0.0, geometry.discs);
  return geometry;
}

// The first scheduled blink's onset.
double first_blink_onset(const EyeModel& eye) { return eye.eyelids().blink_onset_s(1); }

// A time after 1 s with no blink.
double open_time(const EyeModel& eye) {
  double t = 1.0;
  while (eye.eyelids().blink_closure(t) != 0.0) t += 0.01;
  return t;
}

// A time within the first blink where the lids are at least half closed.
double mid_blink(const EyeModel& eye) {
  return first_blink_onset(eye) + eye.parameters().blink_closing_duration_s;
}

struct KeyCase {
  std::string line;  // "key = value"
  std::function<void(const EyeModel& changed, const EyeModel& base)> check;
};

std::string key_of(const std::string& line) { return line.substr(0, line.find(' ')); }

void add(std::vector<KeyCase>& cases, const std::string& line,
         std::function<void(const EyeModel&, const EyeModel&)> check) {
  cases.push_back({line, std::move(check)});
}

void pupil_cases(std::vector<KeyCase>& cases) {
  // --- Pupil and hippus: Eq. 1's amplitude factor (p_max / p) sqrt(1 - p / p_max) times the scale.
  add(cases, "pupil_max_diameter_mm = 11.0", [](const EyeModel& e, const EyeModel& b) {
    EXPECT_NEAR(e.pupil().hippus_amplitude_mm(3.0), 0.1 * (11.0 / 3.0) * std::sqrt(1.0 - 3.0 / 11.0), 1e-12);
    EXPECT_NEAR(b.pupil().hippus_amplitude_mm(3.0), 0.1 * (9.0 / 3.0) * std::sqrt(1.0 - 3.0 / 9.0), 1e-12);
  });
  add(cases, "pupil_min_diameter_mm = 5.0", [](const EyeModel& e, const EyeModel& b) {
    // Eq. 2 at 100 cd/m2 is 2.4 mm: the clamp holds the pupil at 5 mm throughout.
    for (double t = 0.0; t < 10.0; t += 0.37) {
      EXPECT_EQ(e.state_at(t).pupil_diameter_mm, 5.0) << t;
      EXPECT_LT(b.state_at(t).pupil_diameter_mm, 4.0) << t;
    }
  });
  add(cases, "hippus_noise_amplitude = 0.2", [](const EyeModel& e, const EyeModel& b) {
    // The same noise twice as large: the pupil's deviation from Eq. 2 doubles at every instant, so its
    // variance quadruples (no clamp is reached: 2.4 mm +- 0.64 mm).
    double variance_e = 0.0, variance_b = 0.0;
    for (double t = 0.0; t < 30.0; t += 0.05) {
      const EyeState se = e.state_at(t), sb = b.state_at(t);
      const double de = se.pupil_diameter_mm - se.mean_pupil_diameter_mm;
      const double db = sb.pupil_diameter_mm - sb.mean_pupil_diameter_mm;
      EXPECT_NEAR(de, 2.0 * db, 1e-12) << t;
      variance_e += de * de;
      variance_b += db * db;
    }
    EXPECT_GT(variance_b, 0.0);
    EXPECT_NEAR(variance_e / variance_b, 4.0, 1e-9);
  });
  // Field luminance: L(t) = Y + (L0 - Y) exp(-t / tau(Y)), tau = s tau_rod + (1 - s) tau_cone,
  // s = Y_half / (Y_half + Y) (Luidolt 2020 Eqs. 5.2-5.4), from L0 = 100 cd/m2.
  const auto field_after = [](const EyeParameters& p, double y, double t) {
    const double s = p.field_luminance_rod_half_sensitivity_cd_m2 / (p.field_luminance_rod_half_sensitivity_cd_m2 + y);
    const double tau = s * p.field_luminance_rod_time_constant_s + (1.0 - s) * p.field_luminance_cone_time_constant_s;
    return y + (100.0 - y) * std::exp(-t / tau);
  };
  const auto field_check = [field_after](double y) {
    return [field_after, y](const EyeModel& e, const EyeModel& b) {
      EyeModel changed(e.parameters(), kSeed), base(b.parameters(), kSeed);
      changed.record_frame_luminance(0.0, y);
      base.record_frame_luminance(0.0, y);
      const double t = 0.3;
      const double expected = field_after(e.parameters(), y, t);
      EXPECT_NEAR(changed.state_at(t).field_luminance_cd_m2, expected, 1e-9 * expected);
      EXPECT_GT(std::abs(base.state_at(t).field_luminance_cd_m2 - expected), 0.01 * expected);
    };
  };
  add(cases, "field_luminance_rod_time_constant_s = 2.0", field_check(0.001));
  add(cases, "field_luminance_cone_time_constant_s = 0.5", field_check(1000.0));
  add(cases, "field_luminance_rod_half_sensitivity_cd_m2 = 10.0", field_check(10.0));
}

void accommodation_cases(std::vector<KeyCase>& cases) {
  // --- Accommodation microfluctuations.
  add(cases, "accommodative_demand_dioptres = 3.0", [](const EyeModel& e, const EyeModel& b) {
    for (double t = 0.0; t < 5.0; t += 0.5) {
      const EyeState s = e.state_at(t);
      EXPECT_NEAR(s.accommodation_dioptres - s.defocus_dioptres, 3.0, 1e-12);
      EXPECT_NEAR(s.defocus_dioptres, b.state_at(t).defocus_dioptres, 1e-12);  // the fluctuation is the same
    }
  });
  add(cases, "accommodation_low_frequency_rms_dioptres_per_mm = 0.04", [](const EyeModel& e, const EyeModel& b) {
    EXPECT_NEAR(e.accommodation().low_frequency_rms_dioptres(4.0), 0.16, 1e-12);
    for (double t = 0.1; t < 20.0; t += 0.7)
      EXPECT_NEAR(e.accommodation().low_frequency_dioptres(t, 4.0), 2.0 * b.accommodation().low_frequency_dioptres(t, 4.0),
                  1e-12);
  });
  add(cases, "accommodation_low_frequency_max_hz = 1.2", [](const EyeModel& e, const EyeModel& b) {
    // Twice the bandwidth: the same noise run twice as fast.
    for (double t = 0.1; t < 20.0; t += 0.7)
      EXPECT_NEAR(e.accommodation().low_frequency_dioptres(t, 4.0), b.accommodation().low_frequency_dioptres(2.0 * t, 4.0),
                  1e-9);
  });
  // The high-frequency component's frequency, counted by its zero crossings over 100 s.
  const auto crossings_hz = [](const EyeModel& eye) {
    int crossings = 0;
    double previous = eye.accommodation().high_frequency_dioptres(0.0);
    for (double t = 0.001; t < 100.0; t += 0.001) {
      const double now = eye.accommodation().high_frequency_dioptres(t);
      if ((now > 0.0) != (previous > 0.0)) ++crossings;
      previous = now;
    }
    return crossings / 200.0;
  };
  add(cases, "accommodation_high_frequency_centre_hz = 1.9", [crossings_hz](const EyeModel& e, const EyeModel& b) {
    EXPECT_NEAR(crossings_hz(e), 1.9, 0.05);
    EXPECT_NEAR(crossings_hz(b), 1.7, 0.05);
  });
  add(cases, "accommodation_high_frequency_half_width_hz = 0.1", [](const EyeModel& e, const EyeModel& b) {
    double widest_e = 0.0, widest_b = 0.0;
    for (double t = 0.0; t < 200.0; t += 0.01) {
      widest_e = std::max(widest_e, std::abs(e.accommodation().high_frequency_instantaneous_hz(t) - 1.7));
      widest_b = std::max(widest_b, std::abs(b.accommodation().high_frequency_instantaneous_hz(t) - 1.7));
    }
    EXPECT_LE(widest_e, 0.1);
    EXPECT_GT(widest_b, 0.1);
  });
  add(cases, "accommodation_high_frequency_rms_dioptres = 0.08", [](const EyeModel& e, const EyeModel& b) {
    double square = 0.0;
    int n = 0;
    for (double t = 0.0; t < 100.0; t += 0.003, ++n) {
      const double value = e.accommodation().high_frequency_dioptres(t);
      EXPECT_NEAR(value, 2.0 * b.accommodation().high_frequency_dioptres(t), 1e-12);
      square += value * value;
    }
    EXPECT_NEAR(std::sqrt(square / n), 0.08, 0.004);
  });
}

void lens_cases(std::vector<KeyCase>& cases) {
  // --- Lens.
  add(cases, "lens_particle_count = 1500", [](const EyeModel& e, const EyeModel& b) {
    EXPECT_EQ(count_discs(e.geometry_at(1.0), ApertureComponent::lens), 1500u);
    // Babinet: each opaque particle diffracts the light its area blocks, so the scattered energy in
    // the PSF's wings grows with the particles' summed area: twice the particles (the first 750 are
    // the base eye's, the rest drawn alike), about twice the wing energy above the clear pupil's.
    ApertureGeometry clear;
    clear.pupil_diameter_mm = 7.0;
    const double pupil = wing_energy(clear);
    const double more = wing_energy(lens_particles_only(e)) - pupil, fewer = wing_energy(lens_particles_only(b)) - pupil;
    std::printf("lens particles' wing energy above the clear pupil's (%.3e): 750 -> %.3e, 1500 -> %.3e (x %.2f)\n",
                pupil, fewer, more, more / fewer);
    EXPECT_GT(fewer, 0.0);
    EXPECT_NEAR(more / fewer, 2.0, 0.3);
  });
  add(cases, "lens_equatorial_radius_mm = 3.0", [](const EyeModel& e, const EyeModel& b) {
    double widest_e = 0.0, widest_b = 0.0;
    for (const LensParticle& particle : e.lens().particles()) widest_e = std::max(widest_e, particle.r_mm);
    for (const LensParticle& particle : b.lens().particles()) widest_b = std::max(widest_b, particle.r_mm);
    EXPECT_LE(widest_e, 3.0);
    EXPECT_GT(widest_e, 2.8);
    EXPECT_GT(widest_b, 3.0);
  });
  add(cases, "lens_thickness_mm = 2.0", [](const EyeModel& e, const EyeModel& b) {
    double deepest_e = 0.0, deepest_b = 0.0;
    for (const LensParticle& particle : e.lens().particles()) deepest_e = std::max(deepest_e, std::abs(particle.z_mm));
    for (const LensParticle& particle : b.lens().particles()) deepest_b = std::max(deepest_b, std::abs(particle.z_mm));
    EXPECT_LE(deepest_e, 1.0);
    EXPECT_GT(deepest_e, 0.8);
    EXPECT_GT(deepest_b, 1.0);
  });
  const auto diameters = [](const EyeModel& eye) {
    std::pair<double, double> range{1e9, 0.0};
    for (const ApertureDisc& disc : eye.geometry_at(1.0).discs)
      if (disc.component == ApertureComponent::lens)
        range = {std::min(range.first, 2.0 * disc.radius_mm), std::max(range.second, 2.0 * disc.radius_mm)};
    return range;
  };
  add(cases, "lens_particle_diameter_min_mm = 0.015", [diameters](const EyeModel& e, const EyeModel& b) {
    EXPECT_GE(diameters(e).first, 0.015 - 1e-15);
    EXPECT_LE(diameters(e).second, 0.020 + 1e-15);
    EXPECT_LT(diameters(b).first, 0.006);
  });
  add(cases, "lens_particle_diameter_max_mm = 0.008", [diameters](const EyeModel& e, const EyeModel& b) {
    EXPECT_GE(diameters(e).first, 0.005 - 1e-15);
    EXPECT_LE(diameters(e).second, 0.008 + 1e-15);
    EXPECT_GT(diameters(b).second, 0.019);
  });
  add(cases, "lens_deformation_grid_nodes = 9", [](const EyeModel& e, const EyeModel& b) {
    EXPECT_EQ(e.lens().deformation().nodes_per_side(), 9);
    EXPECT_EQ(b.lens().deformation().nodes_per_side(), 17);
    EXPECT_LT(e.lens().deformation().residual(), 1e-9);  // the 9 x 9 grid solved to equilibrium
    // The equator (the driver node) moves by the prescribed displacement on either grid.
    const double equator = e.lens().deformation().displacement(4.5, 0.0, 0.03).radial_mm;
    EXPECT_NEAR(equator, 0.03, 1e-9);
  });
  add(cases, "lens_equator_displacement_mm_per_dioptre = 0.06", [](const EyeModel& e, const EyeModel& b) {
    EXPECT_NEAR(e.lens().equator_displacement_mm(0.5), -0.03, 1e-15);
    for (double t = 0.5; t < 3.0; t += 0.5)
      EXPECT_NEAR(e.state_at(t).lens_equator_displacement_mm, 2.0 * b.state_at(t).lens_equator_displacement_mm, 1e-15);
  });
  add(cases, "lens_grating_count = 400", [](const EyeModel& e, const EyeModel& b) {
    EXPECT_EQ(e.lens().grating_lines().size(), 400u * 8u);
    EXPECT_EQ(b.lens().grating_lines().size(), 200u * 8u);
  });
  // Within a grating the membranes are parallel, one period apart (Spencer 1995 Eq. 4's e).
  const auto spacing = [](const std::vector<ApertureLine>& lines) {
    return std::hypot(lines[1].x0_mm - lines[0].x0_mm, lines[1].y0_mm - lines[0].y0_mm);
  };
  add(cases, "lens_grating_lines_per_grating = 4", [spacing](const EyeModel& e, const EyeModel&) {
    const std::vector<ApertureLine>& lines = e.lens().grating_lines();
    ASSERT_EQ(lines.size(), 200u * 4u);
    // Line 4 starts the second grating: not one period from line 3.
    EXPECT_NEAR(spacing(lines), e.parameters().lens_grating_period_mm, 1e-12);
    EXPECT_GT(std::hypot(lines[4].x0_mm - lines[3].x0_mm, lines[4].y0_mm - lines[3].y0_mm), 0.05);
  });
  add(cases, "lens_grating_period_mm = 0.02", [spacing](const EyeModel& e, const EyeModel& b) {
    EXPECT_NEAR(spacing(e.lens().grating_lines()), 0.02, 1e-12);
    EXPECT_NEAR(spacing(b.lens().grating_lines()), 0.000568 / std::sin(3.0 * std::numbers::pi / 180.0), 1e-9);
  });
  add(cases, "lens_grating_line_width_fraction = 0.25", [](const EyeModel& e, const EyeModel&) {
    for (const ApertureLine& line : e.lens().grating_lines())
      ASSERT_NEAR(line.width_mm, 0.25 * e.parameters().lens_grating_period_mm, 1e-15);
  });
  add(cases, "lens_grating_transmittance = 0.2", [](const EyeModel& e, const EyeModel&) {
    // In the aperture of a wide pupil (gratings in the pupil).
    EyeModel dark(e.parameters(), kSeed);
    dark.record_frame_luminance(0.0, 0.001);
    const std::vector<ApertureLine> lines = lines_of(dark.geometry_at(5.0), ApertureComponent::gratings);
    ASSERT_FALSE(lines.empty());
    for (const ApertureLine& line : lines) ASSERT_EQ(line.transmittance, 0.2);
  });
  add(cases, "lens_grating_length_mm = 0.3", [](const EyeModel& e, const EyeModel&) {
    for (const ApertureLine& line : e.lens().grating_lines())
      ASSERT_NEAR(std::hypot(line.x1_mm - line.x0_mm, line.y1_mm - line.y0_mm), 0.3, 1e-12);
  });
  add(cases, "lens_cortex_inner_radius_mm = 2.5", [](const EyeModel& e, const EyeModel& b) {
    double nearest = 1e9;
    for (const ApertureLine& line : e.lens().grating_lines()) nearest = std::min(nearest, std::hypot(line.x0_mm, line.y0_mm));
    EXPECT_GE(nearest, 2.5);
    // A 4.9 mm pupil uncovers the base eye's gratings (cortex from 1.5 mm) but not these.
    EXPECT_FALSE(e.lens().gratings_visible(4.9));
    EXPECT_TRUE(b.lens().gratings_visible(4.9));
  });
}

void vitreous_cases(std::vector<KeyCase>& cases) {
  // --- Vitreous.
  add(cases, "vitreous_particle_count = 244", [](const EyeModel& e, const EyeModel&) {
    EXPECT_EQ(count_discs(e.geometry_at(1.0), ApertureComponent::vitreous), 244u);
  });
  add(cases, "vitreous_particle_diameter_mm = 0.04", [](const EyeModel& e, const EyeModel&) {
    for (const ApertureDisc& disc : e.geometry_at(1.0).discs)
      if (disc.component == ApertureComponent::vitreous) {
        ASSERT_NEAR(disc.radius_mm, 0.02, 1e-15);
      }
  });
  add(cases, "vitreous_sampling_radius_mm = 3.0", [](const EyeModel& e, const EyeModel& b) {
    double widest_e = 0.0, widest_b = 0.0;
    for (const auto& particle : e.vitreous().particles()) widest_e = std::max(widest_e, std::hypot(particle.x_mm, particle.y_mm));
    for (const auto& particle : b.vitreous().particles()) widest_b = std::max(widest_b, std::hypot(particle.x_mm, particle.y_mm));
    EXPECT_LE(widest_e, 3.0);
    EXPECT_GT(widest_b, 3.0);
  });
  const auto depth_range = [](const EyeModel& eye) {
    std::pair<double, double> range{1e9, -1e9};
    for (const auto& particle : eye.vitreous().particles())
      range = {std::min(range.first, particle.depth_from_rotation_centre_mm),
               std::max(range.second, particle.depth_from_rotation_centre_mm)};
    return range;
  };
  add(cases, "vitreous_front_depth_mm = 8.0", [depth_range](const EyeModel& e, const EyeModel& b) {
    EXPECT_GE(depth_range(e).first, 8.0 - 10.0);
    EXPECT_LT(depth_range(b).first, 8.0 - 10.0);
  });
  add(cases, "vitreous_back_depth_mm = 12.0", [depth_range](const EyeModel& e, const EyeModel& b) {
    EXPECT_LE(depth_range(e).second, 12.0 - 10.0);
    EXPECT_GT(depth_range(b).second, 12.0 - 10.0);
  });
  add(cases, "eye_rotation_centre_depth_mm = 12.0", [](const EyeModel& e, const EyeModel& b) {
    // The same particles, 2 mm nearer the new centre of rotation; rotated, they sweep less far.
    const auto& moved = e.vitreous().particles();
    const auto& base = b.vitreous().particles();
    ASSERT_EQ(moved.size(), base.size());
    for (std::size_t k = 0; k < moved.size(); ++k)
      ASSERT_NEAR(moved[k].depth_from_rotation_centre_mm, base[k].depth_from_rotation_centre_mm - 2.0, 1e-12);
  });
  add(cases, "vitreous_natural_frequency_hz = 1.0", [](const EyeModel& e, const EyeModel& b) {
    EXPECT_LT(vitreous_error(e.parameters()), 0.03);
    EXPECT_GT(std::abs(exact_vitreous_angle(e.parameters(), 0.1, 0.5) - exact_vitreous_angle(b.parameters(), 0.1, 0.5)),
              0.1 * std::abs(exact_vitreous_angle(b.parameters(), 0.1, 0.5)));
  });
  add(cases, "vitreous_damping_ratio = 3.0", [](const EyeModel& e, const EyeModel& b) {
    EXPECT_LT(vitreous_error(e.parameters()), 0.03);
    EXPECT_GT(std::abs(exact_vitreous_angle(e.parameters(), 0.1, 1.0) - exact_vitreous_angle(b.parameters(), 0.1, 1.0)),
              0.1 * std::abs(exact_vitreous_angle(b.parameters(), 0.1, 1.0)));
  });
  add(cases, "vitreous_time_step_s = 0.00025", [](const EyeModel& e, const EyeModel& b) {
    // Forward Euler's error is first order in the step: a quarter of the step, about a quarter of it.
    const double fine = vitreous_error(e.parameters()), coarse = vitreous_error(b.parameters());
    std::printf("vitreous Euler error against the closed form: step 1 ms %.3e, 0.25 ms %.3e\n", coarse, fine);
    EXPECT_NEAR(fine / coarse, 0.25, 0.05);
  });
  add(cases, "saccade_mean_interval_s = 0.25", [](const EyeModel& e, const EyeModel& b) {
    EXPECT_EQ(e.vitreous().dynamics().saccades_between(0.0, 100.0).size(), 400u);
    EXPECT_EQ(b.vitreous().dynamics().saccades_between(0.0, 100.0).size(), 200u);
  });
  add(cases, "saccade_impulse_sd_rad_s = 0.2", [](const EyeModel& e, const EyeModel& b) {
    const std::vector<Saccade> more = e.vitreous().dynamics().saccades_between(0.0, 100.0);
    const std::vector<Saccade> base = b.vitreous().dynamics().saccades_between(0.0, 100.0);
    ASSERT_EQ(more.size(), base.size());
    double square = 0.0;
    for (std::size_t k = 0; k < more.size(); ++k) {
      EXPECT_NEAR(more[k].impulse_rad_s, 2.0 * base[k].impulse_rad_s, 1e-15);
      square += more[k].impulse_rad_s * more[k].impulse_rad_s;
    }
    EXPECT_NEAR(std::sqrt(square / static_cast<double>(more.size())), 0.2, 0.03);  // 200 normal draws of sd 0.2
  });
  add(cases, "saccade_force_decay_s = 0.05", [](const EyeModel& e, const EyeModel& b) {
    EXPECT_LT(vitreous_error(e.parameters()), 0.03);
    EXPECT_GT(std::abs(exact_vitreous_angle(e.parameters(), 0.1, 0.05) - exact_vitreous_angle(b.parameters(), 0.1, 0.05)),
              0.1 * std::abs(exact_vitreous_angle(b.parameters(), 0.1, 0.05)));
  });
}

void static_particle_cases(std::vector<KeyCase>& cases) {
  // --- Cornea and retina.
  add(cases, "cornea_particle_count = 800", [](const EyeModel& e, const EyeModel&) {
    EXPECT_EQ(count_discs(e.geometry_at(1.0), ApertureComponent::cornea), 800u);
  });
  add(cases, "cornea_particle_diameter_mm = 0.03", [](const EyeModel& e, const EyeModel&) {
    for (const ApertureDisc& disc : e.geometry_at(1.0).discs)
      if (disc.component == ApertureComponent::cornea) {
        ASSERT_NEAR(disc.radius_mm, 0.015, 1e-15);
      }
  });
  add(cases, "retina_particle_count = 82", [](const EyeModel& e, const EyeModel&) {
    EXPECT_EQ(count_discs(e.geometry_at(1.0), ApertureComponent::retina), 82u);
  });
  add(cases, "retina_particle_diameter_mm = 0.08", [](const EyeModel& e, const EyeModel&) {
    for (const ApertureDisc& disc : e.geometry_at(1.0).discs)
      if (disc.component == ApertureComponent::retina) {
        ASSERT_NEAR(disc.radius_mm, 0.04, 1e-15);
      }
  });
  add(cases, "static_particle_region_radius_mm = 2.0", [](const EyeModel& e, const EyeModel& b) {
    const auto widest = [](const EyeModel& eye) {
      double r = 0.0;
      for (const ApertureDisc& disc : eye.geometry_at(1.0).discs)
        if (disc.component == ApertureComponent::cornea || disc.component == ApertureComponent::retina)
          r = std::max(r, std::hypot(disc.centre_x_mm, disc.centre_y_mm));
      return r;
    };
    EXPECT_LE(widest(e), 2.0);
    EXPECT_GT(widest(b), 2.0);
  });
}

void blink_cases(std::vector<KeyCase>& cases) {
  // --- Blinks: one per interval; closing, closed and opening phases.
  add(cases, "blink_mean_interval_s = 10.0", [](const EyeModel& e, const EyeModel& b) {
    for (std::int64_t k = 0; k < 20; ++k) {
      EXPECT_GE(e.eyelids().blink_onset_s(k), 10.0 * static_cast<double>(k));
      EXPECT_LE(e.eyelids().blink_end_s(k), 10.0 * static_cast<double>(k + 1));
    }
    EXPECT_LT(b.eyelids().blink_onset_s(19), 10.0 * 19);
  });
  add(cases, "blink_closing_duration_s = 0.2", [](const EyeModel& e, const EyeModel& b) {
    const double onset_e = first_blink_onset(e), onset_b = first_blink_onset(b);
    EXPECT_LT(e.eyelids().blink_closure(onset_e + 0.15), 0.9);  // still closing
    EXPECT_EQ(e.eyelids().blink_closure(onset_e + 0.21), 1.0);
    EXPECT_EQ(b.eyelids().blink_closure(onset_b + 0.12), 1.0);  // the base eye closed at 0.1 s
  });
  add(cases, "blink_closed_duration_s = 0.5", [](const EyeModel& e, const EyeModel& b) {
    const double onset_e = first_blink_onset(e), onset_b = first_blink_onset(b);
    EXPECT_EQ(e.eyelids().blink_closure(onset_e + 0.1 + 0.45), 1.0);
    EXPECT_LT(b.eyelids().blink_closure(onset_b + 0.1 + 0.1), 1.0);  // opening after 0.05 s closed
  });
  add(cases, "blink_opening_duration_s = 0.5", [](const EyeModel& e, const EyeModel& b) {
    const double onset_e = first_blink_onset(e), onset_b = first_blink_onset(b);
    EXPECT_GT(e.eyelids().blink_closure(onset_e + 0.15 + 0.45), 0.0);
    EXPECT_EQ(e.eyelids().blink_closure(onset_e + 0.15 + 0.51), 0.0);
    EXPECT_EQ(b.eyelids().blink_closure(onset_b + 0.15 + 0.21), 0.0);  // open again after 0.2 s
  });
}

void lid_cases(std::vector<KeyCase>& cases) {
  // --- Lids: the opening of the aperture, rasterised, against the margins' closed form.
  add(cases, "squint_closure = 0.5", [](const EyeModel& e, const EyeModel& b) {
    for (double t = 0.0; t < 10.0; t += 0.1) ASSERT_GE(e.state_at(t).lid_closure, 0.5);
    const double open_t = open_time(e);
    const double closure = e.state_at(open_t).lid_closure;
    EXPECT_EQ(closure, 0.5);
    const Opening squinted = lid_opening(e, closure, 0.0), unsquinted = lid_opening(b, b.state_at(open_t).lid_closure, 0.0);
    const EyeParameters& p = e.parameters();
    std::printf("aperture height at x = 0: open %.3f mm (pupil-limited), squint 0.5 %.3f mm (closed form %.3f)\n",
                unsquinted.top_mm - unsquinted.bottom_mm, squinted.top_mm - squinted.bottom_mm,
                upper_margin(p, 0.5) - lower_margin(p, 0.5));
    EXPECT_NEAR(squinted.top_mm, upper_margin(p, 0.5), 0.03);
    EXPECT_NEAR(squinted.bottom_mm, lower_margin(p, 0.5), 0.03);
    EXPECT_GT(unsquinted.top_mm - unsquinted.bottom_mm, 8.5);
  });
  add(cases, "upper_lid_open_margin_mm = 3.0", [](const EyeModel& e, const EyeModel& b) {
    EXPECT_NEAR(lid_opening(e, 0.0, 0.0).top_mm, 3.0, 0.03);
    EXPECT_NEAR(lid_opening(b, 0.0, 0.0).top_mm, 4.5, 0.03);
  });
  add(cases, "lower_lid_open_margin_mm = -4.0", [](const EyeModel& e, const EyeModel& b) {
    EXPECT_NEAR(lid_opening(e, 0.0, 0.0).bottom_mm, -4.0, 0.03);
    EXPECT_LT(lid_opening(b, 0.0, 0.0).bottom_mm, -4.8);  // the pupil's edge, 4.9 mm down
  });
  add(cases, "lid_meeting_height_mm = -2.0", [](const EyeModel& e, const EyeModel&) {
    const EyeParameters& p = e.parameters();
    const Opening half = lid_opening(e, 0.5, 0.0);
    EXPECT_NEAR(half.top_mm, upper_margin(p, 0.5), 0.03);
    EXPECT_NEAR(half.bottom_mm, lower_margin(p, 0.5), 0.03);
    // Nearly closed, the slit sits at the meeting height.
    const Opening slit = lid_opening(e, 0.9, 0.0);
    EXPECT_NEAR(0.5 * (slit.top_mm + slit.bottom_mm), 0.5 * (upper_margin(p, 0.9) + lower_margin(p, 0.9)), 0.03);
    EXPECT_LT(std::abs(0.5 * (slit.top_mm + slit.bottom_mm) - (-2.0)), 0.6);
  });
  add(cases, "lid_margin_curvature_radius_mm = 10.0", [](const EyeModel& e, const EyeModel& b) {
    // The margins are parabolas y = y_c -+ x^2 / (2 R): 3 mm off the axis the upper lid is 0.45 mm
    // lower than at the centre (0.18 mm for the base eye's 25 mm); lids 0.3 closed, so the pupil's
    // edge does not cut the margin there.
    const double drop_e = lid_opening(e, 0.3, 0.0).top_mm - lid_opening(e, 0.3, 3.0).top_mm;
    const double drop_b = lid_opening(b, 0.3, 0.0).top_mm - lid_opening(b, 0.3, 3.0).top_mm;
    EXPECT_NEAR(drop_e, 9.0 / 20.0, 0.03);
    EXPECT_NEAR(drop_b, 9.0 / 50.0, 0.03);
  });
}

void lash_cases(std::vector<KeyCase>& cases) {
  // --- Lashes, in the aperture during a blink.
  const auto lashes_in_blink = [](const EyeModel& eye) { return lines_of(eye.geometry_at(mid_blink(eye)), ApertureComponent::lashes); };
  add(cases, "upper_eyelash_count = 100", [lashes_in_blink](const EyeModel& e, const EyeModel& b) {
    const auto count_down = [](const std::vector<ApertureLine>& lines) {
      return std::count_if(lines.begin(), lines.end(), [](const ApertureLine& l) { return l.y1_mm < l.y0_mm; });
    };
    EXPECT_EQ(count_down(lashes_in_blink(e)), 100);
    EXPECT_EQ(count_down(lashes_in_blink(b)), 50);
  });
  add(cases, "lower_eyelash_count = 0", [lashes_in_blink](const EyeModel& e, const EyeModel& b) {
    const auto count_up = [](const std::vector<ApertureLine>& lines) {
      return std::count_if(lines.begin(), lines.end(), [](const ApertureLine& l) { return l.y1_mm > l.y0_mm; });
    };
    EXPECT_EQ(count_up(lashes_in_blink(e)), 0);
    EXPECT_EQ(count_up(lashes_in_blink(b)), 25);
  });
  add(cases, "eyelash_width_mm = 0.2", [lashes_in_blink](const EyeModel& e, const EyeModel&) {
    const std::vector<ApertureLine> lashes = lashes_in_blink(e);
    ASSERT_EQ(lashes.size(), 75u);
    for (const ApertureLine& lash : lashes) ASSERT_EQ(lash.width_mm, 0.2);
  });
  // A lash reaches overhang = max (0.2 + 0.8 u) along its tilt.
  const auto reach = [lashes_in_blink](const EyeModel& eye, bool upper) {
    std::pair<double, double> range{1e9, 0.0};
    for (const ApertureLine& l : lashes_in_blink(eye))
      if ((l.y1_mm < l.y0_mm) == upper) {
        const double length = std::hypot(l.x1_mm - l.x0_mm, l.y1_mm - l.y0_mm);
        range = {std::min(range.first, length), std::max(range.second, length)};
      }
    return range;
  };
  add(cases, "upper_eyelash_overhang_max_mm = 2.0", [reach](const EyeModel& e, const EyeModel& b) {
    EXPECT_GE(reach(e, true).first, 0.4 - 1e-12);
    EXPECT_LE(reach(e, true).second, 2.0 + 1e-12);
    EXPECT_GT(reach(e, true).second, 1.5);
    EXPECT_LE(reach(b, true).second, 1.0 + 1e-12);
  });
  add(cases, "lower_eyelash_overhang_max_mm = 1.5", [reach](const EyeModel& e, const EyeModel& b) {
    EXPECT_GE(reach(e, false).first, 0.3 - 1e-12);
    EXPECT_LE(reach(e, false).second, 1.5 + 1e-12);
    EXPECT_GT(reach(e, false).second, 1.0);
    EXPECT_LE(reach(b, false).second, 0.5 + 1e-12);
  });
  add(cases, "eyelash_window_half_width_mm = 3.0", [lashes_in_blink](const EyeModel& e, const EyeModel& b) {
    const auto widest = [&](const EyeModel& eye) {
      double x = 0.0;
      for (const ApertureLine& l : lashes_in_blink(eye)) x = std::max(x, std::abs(l.x0_mm));
      return x;
    };
    EXPECT_LE(widest(e), 3.0);
    EXPECT_GT(widest(b), 3.0);
  });
}

std::vector<KeyCase> key_cases() {
  std::vector<KeyCase> cases;
  for (const auto group : {pupil_cases, accommodation_cases, lens_cases, vitreous_cases, static_particle_cases,
                           blink_cases, lid_cases, lash_cases})
    group(cases);
  return cases;
}

TEST(EyeParametersConfig, NoTableIsTheDefaultEye) {
  const EyeParameters read = eye_read("");
  const EyeParameters defaults;
  for (const EyeParameterKey& key : eye_parameter_keys()) {
    if (key.count != nullptr)
      EXPECT_EQ(read.*key.count, defaults.*key.count) << key.key;
    else
      EXPECT_EQ(read.*key.number, defaults.*key.number) << key.key;
  }
}

TEST(EyeParametersConfig, EveryKeyHasItsTestAndEveryTestItsKey) {
  std::set<std::string> tested, keys;
  for (const KeyCase& c : key_cases()) tested.insert(key_of(c.line));
  for (const EyeParameterKey& key : eye_parameter_keys()) keys.insert(std::string(key.key));
  EXPECT_EQ(tested, keys);
  // Every field of the struct but the three the session sets per eye (mode, static_time_s and the
  // first field luminance): 58 keys.
  EXPECT_EQ(keys.size(), 58u);
}

TEST(EyeParametersConfig, EachKeyChangesWhatItShould) {
  const EyeModel base(EyeParameters{}, kSeed);
  for (const KeyCase& c : key_cases()) {
    SCOPED_TRACE(c.line);
    const EyeParameters read = eye_read(c.line);
    // Only this key differs from the defaults.
    const EyeParameters defaults;
    for (const EyeParameterKey& key : eye_parameter_keys()) {
      const bool same = key.count != nullptr ? read.*key.count == defaults.*key.count : read.*key.number == defaults.*key.number;
      EXPECT_EQ(same, std::string(key.key) != key_of(c.line)) << key.key;
    }
    const EyeModel changed(read, kSeed);
    c.check(changed, base);
  }
}

// The session's eyes are built from [glare.eye]: the glare stage's dynamic eye squints.
TEST(EyeParametersConfig, TheSessionsGlareStageUsesTheTable) {
  GlareSpec spec = parse_experiment_text(experiment_with_eye("squint_closure = 0.6\nlens_particle_count = 10"), "p.toml", "/tmp").glare;
  spec.backend = GlareBackendRequest::cpu;
  spec.grid_px = 64;
  spec.wavelength_samples = 2;
  DisplaySpec display;
  display.width_px = 64;
  display.height_px = 64;
  for (const GlareMode mode : {GlareMode::dynamic, GlareMode::static_eye}) {
    GlareSpec plain_spec = spec;
    plain_spec.eye = EyeParameters{};
    GlareStage squinting(spec, display, kSeed), plain(plain_spec, display, kSeed);
    EyeState squinted, unsquinted;
    ASSERT_TRUE(squinting.display_psf(mode, 0.2, 100.0, &squinted));
    ASSERT_TRUE(plain.display_psf(mode, 0.2, 100.0, &unsquinted));
    EXPECT_GE(squinted.lid_closure, 0.6);
    EXPECT_LT(unsquinted.lid_closure, 0.6);
  }
}

TEST(EyeParametersConfig, TheResolvedExperimentWritesEveryKeyAndReadsBackTheSame) {
  std::string lines;
  // Every case's value at once, but the smaller largest lens particle (below the case's smallest).
  for (const KeyCase& c : key_cases())
    if (key_of(c.line) != "lens_particle_diameter_max_mm") lines += c.line + "\n";
  const Experiment original = parse_experiment_text(experiment_with_eye(lines), "p.toml", "/tmp");
  const std::string resolved = resolved_config_toml(original);
  for (const EyeParameterKey& key : eye_parameter_keys())
    EXPECT_NE(resolved.find(std::string(key.key) + " = "), std::string::npos) << key.key;
  const Experiment reread = parse_experiment_text(resolved, "resolved.toml", "/tmp");
  for (const EyeParameterKey& key : eye_parameter_keys()) {
    if (key.count != nullptr)
      EXPECT_EQ(reread.glare.eye.*key.count, original.glare.eye.*key.count) << key.key;
    else
      EXPECT_EQ(reread.glare.eye.*key.number, original.glare.eye.*key.number) << key.key;
  }
  EXPECT_EQ(reread.glare.eye.squint_closure, 0.5);
}

TEST(EyeParametersConfig, RefusalsNameTheKeyItsPlaceAndItsBounds) {
  EXPECT_EQ(refusal("squint_closure = 1.5"), "p.toml:3:18: key 'glare.eye.squint_closure': must be from 0 to 1, found 1.5");
  EXPECT_EQ(refusal("lens_particle_count = -1"),
            "p.toml:3:23: key 'glare.eye.lens_particle_count': must be an integer from 0 to 100000, found -1");
  EXPECT_EQ(refusal("lens_particle_count = 10.5"),
            "p.toml:3:23: key 'glare.eye.lens_particle_count': expected an integer, found a float");
  EXPECT_EQ(refusal("eyelash_width_mm = 0"),
            "p.toml:3:20: key 'glare.eye.eyelash_width_mm': must be > 0 and at most 1 mm, found 0");
  EXPECT_EQ(refusal("pupil_max_diameter_mm = 7.9"),
            "p.toml:3:25: key 'glare.eye.pupil_max_diameter_mm': must be > 7.9 and at most 12 mm, found 7.9");
  EXPECT_EQ(refusal("hippus_noise_amplitude = \"large\""),
            "p.toml:3:26: key 'glare.eye.hippus_noise_amplitude': expected a number, found a string");
  // Rules between keys, at the key validate() names.
  EXPECT_EQ(refusal("lid_meeting_height_mm = 6.0"),
            "p.toml:3:25: key 'glare.eye.lid_meeting_height_mm': must lie between lower_lid_open_margin_mm and "
            "upper_lid_open_margin_mm");
  EXPECT_EQ(refusal("lens_particle_diameter_min_mm = 0.03"),
            "p.toml:3:33: key 'glare.eye.lens_particle_diameter_min_mm': must not exceed lens_particle_diameter_max_mm");
  const std::string unknown = refusal("squint = 0.5");
  EXPECT_NE(unknown.find("p.toml:3:1: "), std::string::npos) << unknown;
  EXPECT_NE(unknown.find("squint"), std::string::npos) << unknown;
  EXPECT_NE(unknown.find("unknown key"), std::string::npos) << unknown;
  // The three the session sets are not keys of the table.
  EXPECT_NE(refusal("mode = \"static\"").find("unknown key"), std::string::npos);
  EXPECT_NE(refusal("initial_field_luminance_cd_m2 = 10").find("unknown key"), std::string::npos);
}

// Through the command line: `run` and `validate` stop with exit 2 at file:line:column naming the
// key, and no database is written.
TEST(EyeParametersConfig, BadValuesStopTheRunBeforeAnythingIsWritten) {
  const ScratchDir scratch;
  const auto& dir = scratch.path();
  const auto conditions = std::filesystem::path(GLARELAB_SOURCE_DIR) / "examples/demo_conditions.csv";
  const auto base = test::demo_variant(dir, {{"file", "file = \"" + conditions.string() + "\""}});
  const std::string demo = test::read_bytes(base);
  // The demo's lines, a blank line, "[glare.eye]", then the key.
  const int first_line = static_cast<int>(std::count(demo.begin(), demo.end(), '\n')) + 3;
  struct Bad {
    std::string line;
    std::string expected;  // after "path:line:"
  };
  const std::vector<Bad> bad = {
      {"squint_closure = 2", "18: key 'glare.eye.squint_closure': must be from 0 to 1, found 2"},
      {"cornea_particle_count = \"many\"", "25: key 'glare.eye.cornea_particle_count': expected an integer, found a string"},
      {"blink_mean_interval_s = 0.3",
       "25: key 'glare.eye.blink_mean_interval_s': must be longer than one blink (0.35 s)"},
      {"lash_count = 3", "1: "},
  };
  for (const Bad& b : bad) {
    SCOPED_TRACE(b.line);
    const auto experiment = dir / "bad.toml";
    test::write_bytes(experiment.string(), demo + "\n[glare.eye]\n" + b.line + "\n");
    const auto db = dir / "bad.db";
    const auto run = test::run_glarelab(
        {"run", experiment.string(), "--display", "offscreen", "--observer", "simulated", "--db", db.string()}, dir);
    const auto validate = test::run_glarelab({"validate", experiment.string()}, dir);
    EXPECT_EQ(run.exit_code, 2) << run.output;
    EXPECT_EQ(validate.exit_code, 2) << validate.output;
    const std::string where = experiment.string() + ":" + std::to_string(first_line) + ":" + b.expected;
    EXPECT_NE(run.output.find(where), std::string::npos) << run.output;
    EXPECT_NE(validate.output.find(where), std::string::npos) << validate.output;
    EXPECT_NE(run.output.find(key_of(b.line)), std::string::npos) << run.output;
    EXPECT_FALSE(std::filesystem::exists(db));
  }
}

}  // namespace
}  // namespace glarelab
