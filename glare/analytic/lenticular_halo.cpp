#include "glare/analytic/lenticular_halo.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <numbers>
#include <stdexcept>

#include "core/parallel_for.h"
#include "glare/analytic/analytic_psf.h"
#include "glare/eye/eye_parameters.h"

namespace glarelab {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kDegPerRad = 180.0 / kPi;
constexpr double kNmPerMm = 1e6;
// The first-order lobe of the K-slit pattern: half way to the zeroth and the second order.
constexpr double kLobeFrom = 0.5, kLobeTo = 1.5;
constexpr double kTableStepDeg = 0.0005;
// Display pixels are integrated on sub-pixels no wider than this (the ring is 0.33 degrees wide).
constexpr double kSubPixelDeg = 0.01;

// The K-slit far field across the membranes, 1 at the orders: the array factor times one slit's
// envelope (the membrane of width f e), normalised to the envelope's value 1 at x = 0.
double lobe(double x, const HaloGratings& g) {
  const double s = std::sin(kPi * x);
  const double k = g.lines_per_patch;
  const double array = std::abs(s) < 1e-12 ? 1.0 : std::pow(std::sin(k * kPi * x) / (k * s), 2);
  const double a = kPi * g.line_width_fraction * x;
  const double envelope = a == 0.0 ? 1.0 : std::pow(std::sin(a) / a, 2);
  return array * envelope;
}

// Length of the segment p0-p1 inside the disc of radius r about the origin.
double length_inside_disc(double x0, double y0, double x1, double y1, double r) {
  const double dx = x1 - x0, dy = y1 - y0;
  const double a = dx * dx + dy * dy;
  if (a == 0.0) return 0.0;
  const double b = 2.0 * (x0 * dx + y0 * dy), c = x0 * x0 + y0 * y0 - r * r;
  const double discriminant = b * b - 4.0 * a * c;
  if (discriminant <= 0.0) return 0.0;
  const double root = std::sqrt(discriminant);
  const double from = std::max(0.0, (-b - root) / (2.0 * a)), to = std::min(1.0, (-b + root) / (2.0 * a));
  return to > from ? (to - from) * std::sqrt(a) : 0.0;
}

}  // namespace

HaloGratings halo_gratings(const EyeParameters& parameters) {
  return HaloGratings{parameters.lens_grating_period_mm, parameters.lens_grating_lines_per_grating,
                      parameters.lens_grating_line_width_fraction, parameters.lens_grating_transmittance};
}

double first_order_efficiency(const HaloGratings& g) {
  const double c1 = (1.0 - g.transmittance) * std::sin(kPi * g.line_width_fraction) / kPi;
  return 2.0 * c1 * c1;
}

double lenticular_halo_energy(const std::vector<ApertureLine>& grating_lines, const HaloGratings& gratings,
                              double pupil_diameter_mm) {
  const double r = 0.5 * pupil_diameter_mm;
  if (!(r > 0.0) || gratings.line_width_fraction <= 0.0) return 0.0;
  double membranes_mm2 = 0.0;
  for (const ApertureLine& line : grating_lines)
    membranes_mm2 += line.width_mm * length_inside_disc(line.x0_mm, line.y0_mm, line.x1_mm, line.y1_mm, r);
  const double patches_mm2 = membranes_mm2 / gratings.line_width_fraction;
  return std::min(1.0, patches_mm2 / (kPi * r * r)) * first_order_efficiency(gratings);
}

LenticularHalo::LenticularHalo(const HaloGratings& gratings) : gratings_(gratings) {
  if (!(gratings.period_mm > 0.0) || gratings.lines_per_patch < 1)
    throw std::invalid_argument("glare/analytic/lenticular_halo: the gratings need a positive period and at least one line");
  // Simpson on the lobe: K - 1 side lobes between the zeros, 4000 intervals per unit of x.
  const int n = 4000 * gratings.lines_per_patch;
  const double h = (kLobeTo - kLobeFrom) / n;
  double sum = lobe(kLobeFrom, gratings) + lobe(kLobeTo, gratings);
  for (int i = 1; i < n; ++i) sum += (i % 2 == 1 ? 4.0 : 2.0) * lobe(kLobeFrom + i * h, gratings);
  lobe_integral_ = sum * h / 3.0;
  const HaloSpectrum spectrum = spencer_halo_spectrum();
  const double e_nm = gratings.period_mm * kNmPerMm;
  const double from = std::asin(std::min(1.0, kLobeFrom * spectrum.wavelengths_nm.front() / e_nm)) * kDegPerRad;
  const double to = std::asin(std::min(1.0, kLobeTo * spectrum.wavelengths_nm.back() / e_nm)) * kDegPerRad;
  table_start_deg_ = from;
  const auto count = static_cast<std::size_t>(std::ceil((to - from) / kTableStepDeg)) + 2;
  for (int c = 0; c < 3; ++c) table_[static_cast<std::size_t>(c)].assign(count, 0.0);
  for (std::size_t i = 0; i < count; ++i) {
    const double angle = from + static_cast<double>(i) * kTableStepDeg;
    for (std::size_t j = 0; j < spectrum.wavelengths_nm.size(); ++j) {
      const double value = per_sr_at_wavelength(angle, spectrum.wavelengths_nm[j]);
      for (int c = 0; c < 3; ++c)
        table_[static_cast<std::size_t>(c)][i] += spectrum.channel_weights[static_cast<std::size_t>(c)][j] * value;
    }
  }
}

double LenticularHalo::first_order_deg(double wavelength_nm) const {
  return std::asin(wavelength_nm / (gratings_.period_mm * kNmPerMm)) * kDegPerRad;
}

double LenticularHalo::outer_deg() const { return table_start_deg_ + static_cast<double>(table_[0].size() - 1) * kTableStepDeg; }

double LenticularHalo::per_sr_at_wavelength(double angle_deg, double wavelength_nm) const {
  const double theta = angle_deg / kDegPerRad;
  if (!(theta > 0.0) || theta >= kPi / 2.0) return 0.0;
  const double e_over_lambda = gratings_.period_mm * kNmPerMm / wavelength_nm;
  const double x = e_over_lambda * std::sin(theta);
  if (x < kLobeFrom || x > kLobeTo) return 0.0;
  // Energy per radian of theta, I(x) dx/dtheta over the lobe's integral, spread over the ring's
  // solid angle 2 pi sin(theta) dtheta.
  const double per_radian = lobe(x, gratings_) * e_over_lambda * std::cos(theta) / lobe_integral_;
  return per_radian / (2.0 * kPi * std::sin(theta));
}

double LenticularHalo::per_sr(double angle_deg, int channel) const {
  const std::vector<double>& table = table_[static_cast<std::size_t>(channel)];
  const double at = (angle_deg - table_start_deg_) / kTableStepDeg;
  if (!(at >= 0.0) || at >= static_cast<double>(table.size() - 1)) return 0.0;
  const auto i = static_cast<std::size_t>(at);
  const double t = at - static_cast<double>(i);
  return (1.0 - t) * table[i] + t * table[i + 1];
}

DisplayKernel lenticular_halo_kernel(const LenticularHalo& halo, const DisplayGeometry& geometry, int threads) {
  const double d = geometry.viewing_distance_mm, pitch = geometry.pixel_pitch_mm;
  const int half = static_cast<int>(std::ceil(d * std::tan(halo.outer_deg() / kDegPerRad) / pitch)) + 1;
  DisplayKernel kernel;
  kernel.half_width_px = kernel.half_height_px = half;
  kernel.channels = 3;
  const std::size_t plane = static_cast<std::size_t>(kernel.width_px()) * kernel.height_px();
  kernel.values.assign(3 * plane, 0.0);
  const double pixel_deg = std::atan(pitch / d) * kDegPerRad;
  const int n = std::max(3, static_cast<int>(std::ceil(pixel_deg / kSubPixelDeg)));
  const double sub = pitch / n, sub_area = sub * sub;
  parallel_indexed_chunks(kernel.height_px(), threads, [&](int, int row_from, int row_to) {
    for (int row = row_from; row < row_to; ++row) {
      const int dy = row - half;
      for (int dx = -half; dx <= half; ++dx) {
        // Pixels wholly inside or outside the ring's angles get nothing.
        const double r_px = std::hypot(dx, dy);
        const double near_deg = std::atan(std::max(0.0, r_px - 0.7072) * pitch / d) * kDegPerRad;
        const double far_deg = std::atan((r_px + 0.7072) * pitch / d) * kDegPerRad;
        if (far_deg < halo.inner_deg() || near_deg > halo.outer_deg()) continue;
        std::array<double, 3> sum{0.0, 0.0, 0.0};
        for (int b = 0; b < n; ++b)
          for (int a = 0; a < n; ++a) {
            const double x = (dx - 0.5 + (a + 0.5) / n) * pitch, y = (dy - 0.5 + (b + 0.5) / n) * pitch;
            const double r2 = x * x + y * y;
            const double angle_deg = std::atan(std::sqrt(r2) / d) * kDegPerRad;
            const double solid_angle = d * sub_area / std::pow(d * d + r2, 1.5);
            for (int c = 0; c < 3; ++c) sum[static_cast<std::size_t>(c)] += halo.per_sr(angle_deg, c) * solid_angle;
          }
        const std::size_t index = static_cast<std::size_t>(row) * kernel.width_px() + (dx + half);
        for (int c = 0; c < 3; ++c) kernel.values[c * plane + index] = sum[static_cast<std::size_t>(c)];
      }
    }
  });
  return kernel;
}

LenticularHaloGlare::LenticularHaloGlare(const LenticularHalo& halo, const DisplayGeometry& geometry, int width_px,
                                         int height_px, int threads)
    : width_px_(width_px), height_px_(height_px) {
  const DisplayKernel kernel = lenticular_halo_kernel(halo, geometry, threads);
  convolution_ = std::make_unique<DisplayKernelConvolution>(width_px, height_px, kernel.half_width_px,
                                                            kernel.half_height_px, threads);
  convolution_->set_components({kernel});
  convolution_->set_weights({1.0});
}

void LenticularHaloGlare::add(const ImageRGBA& source_energy, double halo_energy, ImageRGBA& glared_energy) {
  if (!(halo_energy > 0.0)) return;
  if (glared_energy.width_px != source_energy.width_px || glared_energy.height_px != source_energy.height_px)
    throw std::invalid_argument("glare/analytic/lenticular_halo: the glared frame and its source differ in size");
  const bool same = kept_ && last_source_.width_px == source_energy.width_px &&
                    last_source_.height_px == source_energy.height_px &&
                    std::memcmp(last_source_.rgba.data(), source_energy.rgba.data(),
                                source_energy.rgba.size() * sizeof(float)) == 0;
  if (!same) {
    convolution_->convolve(source_energy, last_ring_);
    last_source_ = source_energy;
    kept_ = true;
    ++convolutions_computed_;
  }
  for (std::size_t i = 0; i < glared_energy.rgba.size(); i += 4)
    for (std::size_t c = 0; c < 3; ++c)
      glared_energy.rgba[i + c] += static_cast<float>(
          halo_energy * (static_cast<double>(last_ring_.rgba[i + c]) - static_cast<double>(source_energy.rgba[i + c])));
}

}  // namespace glarelab
