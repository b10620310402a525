#include "glare/eye/lens_model.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "glare/eye/eye_random_channels.h"
#include "core/random.h"

namespace glarelab {

namespace {

constexpr double kPi = 3.14159265358979323846;

struct Spring {
  int a, b;        // node indices
  double nx, ny;   // unit rest direction (radial, axial)
};

// K u for linear springs of unit stiffness: each spring pulls its ends along its rest direction by
// the stretch n . (u_b - u_a).
void apply_stiffness(const std::vector<Spring>& springs, const std::vector<double>& u, std::vector<double>& out) {
  std::fill(out.begin(), out.end(), 0.0);
  for (const Spring& s : springs) {
    const auto a = static_cast<std::size_t>(s.a) * 2, b = static_cast<std::size_t>(s.b) * 2;
    const double stretch = s.nx * (u[b] - u[a]) + s.ny * (u[b + 1] - u[a + 1]);
    out[a] -= stretch * s.nx;
    out[a + 1] -= stretch * s.ny;
    out[b] += stretch * s.nx;
    out[b + 1] += stretch * s.ny;
  }
}

}  // namespace

LensDeformation::LensDeformation(const EyeParameters& p)
    : nodes_(p.lens_deformation_grid_nodes),
      radius_mm_(p.lens_equatorial_radius_mm),
      half_thickness_mm_(0.5 * p.lens_thickness_mm) {
  const int n = nodes_;
  const auto node_count = static_cast<std::size_t>(n) * static_cast<std::size_t>(n);
  const double dr = radius_mm_ / (n - 1), dz = 2.0 * half_thickness_mm_ / (n - 1);
  std::vector<Spring> springs;
  auto add = [&](int i0, int j0, int i1, int j1) {
    if (i1 < 0 || i1 >= n || j1 < 0 || j1 >= n) return;
    const double x = (i1 - i0) * dr, y = (j1 - j0) * dz, length = std::hypot(x, y);
    springs.push_back(Spring{i0 * n + j0, i1 * n + j1, x / length, y / length});
  };
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      add(i, j, i + 1, j);      // structural
      add(i, j, i, j + 1);
      add(i, j, i + 1, j + 1);  // shear
      add(i, j, i + 1, j - 1);
    }
  // Constraints: the axis moves only along the axis; the driver (equator) node is moved by a unit radial
  // displacement and held axially.
  const int driver = (n - 1) * n + n / 2;
  std::vector<char> fixed(node_count * 2, 0);
  std::vector<double> u(node_count * 2, 0.0);
  for (int j = 0; j < n; ++j) fixed[static_cast<std::size_t>(j) * 2] = 1;
  fixed[static_cast<std::size_t>(driver) * 2] = fixed[static_cast<std::size_t>(driver) * 2 + 1] = 1;
  u[static_cast<std::size_t>(driver) * 2] = 1.0;

  // Solve K_ff u_f = -K_fc u_c by conjugate gradients (K is symmetric positive definite once the
  // rigid motions are removed by the constraints).
  std::vector<double> ku(u.size()), r(u.size()), d(u.size()), kd(u.size());
  apply_stiffness(springs, u, ku);
  for (std::size_t k = 0; k < u.size(); ++k) r[k] = fixed[k] ? 0.0 : -ku[k];
  d = r;
  double rr = 0.0;
  for (double v : r) rr += v * v;
  const double tolerance = 1e-28;
  for (std::size_t iteration = 0; iteration < 20 * u.size() && rr > tolerance; ++iteration) {
    apply_stiffness(springs, d, kd);
    double dkd = 0.0;
    for (std::size_t k = 0; k < u.size(); ++k)
      if (!fixed[k]) dkd += d[k] * kd[k];
    const double alpha = rr / dkd;
    double rr_next = 0.0;
    for (std::size_t k = 0; k < u.size(); ++k) {
      if (fixed[k]) continue;
      u[k] += alpha * d[k];
      r[k] -= alpha * kd[k];
      rr_next += r[k] * r[k];
    }
    const double beta = rr_next / rr;
    rr = rr_next;
    for (std::size_t k = 0; k < u.size(); ++k) d[k] = fixed[k] ? 0.0 : r[k] + beta * d[k];
  }
  apply_stiffness(springs, u, ku);
  for (std::size_t k = 0; k < u.size(); ++k)
    if (!fixed[k]) residual_ = std::max(residual_, std::abs(ku[k]));
  unit_radial_.resize(node_count);
  unit_axial_.resize(node_count);
  for (std::size_t k = 0; k < node_count; ++k) {
    unit_radial_[k] = u[2 * k];
    unit_axial_[k] = u[2 * k + 1];
  }
}

LensDeformation::Displacement LensDeformation::node_unit_response(int i, int j) const {
  const auto k = static_cast<std::size_t>(i * nodes_ + j);
  return {unit_radial_[k], unit_axial_[k]};
}

LensDeformation::Displacement LensDeformation::displacement(double r_mm, double z_mm,
                                                            double equator_displacement_mm) const {
  const int n = nodes_;
  const double gx = std::clamp(r_mm / radius_mm_, 0.0, 1.0) * (n - 1);
  const double gz = std::clamp((z_mm + half_thickness_mm_) / (2.0 * half_thickness_mm_), 0.0, 1.0) * (n - 1);
  const int i = std::min(static_cast<int>(gx), n - 2), j = std::min(static_cast<int>(gz), n - 2);
  const double fx = gx - i, fz = gz - j;
  auto lerp2 = [&](const std::vector<double>& field) {
    const auto at = [&](int a, int b) { return field[static_cast<std::size_t>(a * n + b)]; };
    return (1 - fx) * (1 - fz) * at(i, j) + fx * (1 - fz) * at(i + 1, j) + (1 - fx) * fz * at(i, j + 1) +
           fx * fz * at(i + 1, j + 1);
  };
  return {equator_displacement_mm * lerp2(unit_radial_), equator_displacement_mm * lerp2(unit_axial_)};
}

LensModel::LensModel(const EyeParameters& p, std::uint64_t seed) : parameters_(p), deformation_(p) {
  const CounterRandom random(seed, RandomStream::eye_model);
  const double radius = p.lens_equatorial_radius_mm, half_thickness = 0.5 * p.lens_thickness_mm;
  // Rejection sampling of the lens volume (an ellipsoid of revolution) in the meridional section:
  // a point (r, z) is accepted inside the ellipse and with probability r / R, the volume element of a
  // solid of revolution being 2 pi r dr dz; the angle about the axis is uniform.
  std::uint64_t attempt = 0;
  const auto sub = [](std::uint32_t k) { return eye_sub_index(EyeChannel::lens_particles, k); };
  for (int k = 0; k < p.lens_particle_count; ++k) {
    for (;; ++attempt) {
      if (attempt > 1000u * static_cast<std::uint64_t>(p.lens_particle_count) + 1000u)
        throw std::runtime_error("lens model: rejection sampling of the lens volume did not converge");
      const double r = radius * random.uniform(attempt, sub(0));
      const double z = half_thickness * (2.0 * random.uniform(attempt, sub(1)) - 1.0);
      const double inside = (r / radius) * (r / radius) + (z / half_thickness) * (z / half_thickness);
      if (inside > 1.0 || random.uniform(attempt, sub(2)) >= r / radius) continue;
      const auto index = static_cast<std::uint64_t>(k);
      const double angle = 2.0 * kPi * random.uniform(index, sub(3));
      const double diameter = p.lens_particle_diameter_min_mm +
                              (p.lens_particle_diameter_max_mm - p.lens_particle_diameter_min_mm) *
                                  random.uniform(index, sub(4));
      particles_.push_back(LensParticle{r, z, angle, diameter});
      ++attempt;
      break;
    }
  }

  // Fibre gratings: patches of parallel membranes, oriented radially (the fibres run meridionally),
  // spaced by the fibre period, placed uniformly over the cortex annulus.
  const int lines = p.lens_grating_lines_per_grating;
  const double period = p.lens_grating_period_mm, length = p.lens_grating_length_mm;
  const double half_width = 0.5 * lines * period;
  const double outer = std::sqrt(radius * radius - half_width * half_width);
  const double inner_centre = p.lens_cortex_inner_radius_mm + 0.5 * length, outer_centre = outer - 0.5 * length;
  const auto grating_sub = [](std::uint32_t k) { return eye_sub_index(EyeChannel::lens_gratings, k); };
  grating_min_reach_mm_ = radius;
  for (int g = 0; g < p.lens_grating_count; ++g) {
    const auto index = static_cast<std::uint64_t>(g);
    const double angle = 2.0 * kPi * random.uniform(index, grating_sub(0));
    // Uniform over the annulus area: r^2 uniform.
    const double centre = std::sqrt(inner_centre * inner_centre +
                                    (outer_centre * outer_centre - inner_centre * inner_centre) *
                                        random.uniform(index, grating_sub(1)));
    const double ux = std::cos(angle), uy = std::sin(angle), vx = -uy, vy = ux;
    for (int m = 0; m < lines; ++m) {
      const double offset = (m - 0.5 * (lines - 1)) * period;
      const double r0 = centre - 0.5 * length, r1 = centre + 0.5 * length;
      ApertureLine line;
      line.x0_mm = r0 * ux + offset * vx;
      line.y0_mm = r0 * uy + offset * vy;
      line.x1_mm = r1 * ux + offset * vx;
      line.y1_mm = r1 * uy + offset * vy;
      line.width_mm = p.lens_grating_line_width_fraction * period;
      line.transmittance = p.lens_grating_transmittance;
      line.component = ApertureComponent::gratings;
      grating_lines_.push_back(line);
      grating_min_reach_mm_ = std::min(grating_min_reach_mm_, std::hypot(r0, offset) - 0.5 * line.width_mm);
    }
  }
}

double LensModel::equator_displacement_mm(double accommodation_fluctuation_dioptres) const {
  return -parameters_.lens_equator_displacement_mm_per_dioptre * accommodation_fluctuation_dioptres;
}

void LensModel::append_particles(double equator_displacement_mm, std::vector<ApertureDisc>& discs) const {
  for (const LensParticle& particle : particles_) {
    const auto moved = deformation_.displacement(particle.r_mm, particle.z_mm, equator_displacement_mm);
    const double r = particle.r_mm + moved.radial_mm;
    discs.push_back(ApertureDisc{r * std::cos(particle.angle_rad), r * std::sin(particle.angle_rad),
                                 0.5 * particle.diameter_mm, 0.0});
  }
}

bool LensModel::gratings_visible(double pupil_diameter_mm) const {
  return !grating_lines_.empty() && 0.5 * pupil_diameter_mm > grating_min_reach_mm_;
}

}  // namespace glarelab
