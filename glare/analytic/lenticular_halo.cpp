#include "glare/analytic/lenticular_halo.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <numbers>
#include <stdexcept>
#include <utility>

#include "core/parallel_for.h"
#include "core/same_pixels.h"
#include "glare/analytic/analytic_psf.h"
#include "glare/wave/cie_cmf.h"
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

// A white lamp's spectrum in each channel: a frame's R = G = B pixel is Rec.709's white, D65, so its
// light at lambda is D65(lambda), and the ring it makes, expressed in linear Rec.709, is
// sum_lambda rgb(lambda) D65(lambda) ring_lambda with rgb the Rec.709 rows of the XYZ-to-RGB matrix
// applied to the CIE 1931 functions (glare/wave/cie_cmf.h). The weights keep their signs (a spectral
// colour lies outside Rec.709), each channel's summing to 1: D65's R, G and B sums are equal (within
// the CMF fit's 1e-3), so a white lamp's Rec.709 luminance 0.2126 R + 0.7152 G + 0.0722 B is the
// V(lambda)-weighted ring, whose peak is where the eye sees the halo. Sampled at D65's own 10 nm
// steps, 380-780 nm (41 wavelengths; each ring is 0.33 degrees wide, 10 nm moves it 0.055).
struct RingSpectrum {
  std::vector<double> wavelengths_nm;
  std::array<std::vector<double>, 3> channel_weights;
};
RingSpectrum d65_ring_spectrum() {
  RingSpectrum spectrum;
  std::array<double, 3> sums{0.0, 0.0, 0.0};
  for (double nm = kD65FirstNm; nm <= kD65LastNm + 1e-9; nm += kD65StepNm) {
    const LinearRgb rgb = xyz_to_linear_rec709(cie1931_cmf(nm));
    const double power = cie_d65_relative_power(nm);
    const std::array<double, 3> w{rgb.r * power, rgb.g * power, rgb.b * power};
    spectrum.wavelengths_nm.push_back(nm);
    for (std::size_t c = 0; c < 3; ++c) {
      spectrum.channel_weights[c].push_back(w[c]);
      sums[c] += w[c];
    }
  }
  for (std::size_t c = 0; c < 3; ++c)
    for (double& w : spectrum.channel_weights[c]) w /= sums[c];
  return spectrum;
}

// The ring's colour at one angle brought into Rec.709's gamut at its own luminance: where a channel
// is negative (the cyan between 480 and 540 nm has negative red), the colour is moved towards the
// grey of the same luminance Y just far enough that no channel is below 0,
//   rgb' = Y + a (rgb - Y),   a = min over negative channels of Y / (Y - c).
// Luminance is kept at every angle, so the ring's luminance stays where the eye sees it, and no
// channel of the kernel is negative, so no frame pixel can be (red's negative lobe, 0.4 of its peak
// near 2.7 degrees, would outweigh CIE 146's veil there with a 6 mm pupil).
std::array<double, 3> into_gamut(const std::array<double, 3>& rgb) {
  const double y = luminance_rec709(rgb[0], rgb[1], rgb[2]);
  double a = 1.0;
  for (const double c : rgb)
    if (c < 0.0) a = std::min(a, y > 0.0 ? y / (y - c) : 0.0);
  if (a == 1.0) return rgb;
  std::array<double, 3> out{};
  for (std::size_t c = 0; c < 3; ++c) out[c] = std::max(0.0, y + a * (rgb[c] - y));
  return out;
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
  const RingSpectrum spectrum = d65_ring_spectrum();
  const double e_nm = gratings.period_mm * kNmPerMm;
  const double from = std::asin(std::min(1.0, kLobeFrom * kD65FirstNm / e_nm)) * kDegPerRad;
  const double to = std::asin(std::min(1.0, kLobeTo * kD65LastNm / e_nm)) * kDegPerRad;
  const auto count = static_cast<std::size_t>(std::ceil((to - from) / kTableStepDeg)) + 2;
  for (int c = 0; c < 3; ++c) table_[static_cast<std::size_t>(c)].assign(count, 0.0);
  std::array<double, 3> energy{0.0, 0.0, 0.0};
  for (std::size_t i = 0; i < count; ++i) {
    const double angle = from + static_cast<double>(i) * kTableStepDeg;
    std::array<double, 3> ring{0.0, 0.0, 0.0};
    for (std::size_t j = 0; j < spectrum.wavelengths_nm.size(); ++j) {
      const double value = per_sr_at_wavelength(angle, spectrum.wavelengths_nm[j]);
      for (std::size_t c = 0; c < 3; ++c) ring[c] += spectrum.channel_weights[c][j] * value;
    }
    ring = into_gamut(ring);
    const double solid_angle = 2.0 * kPi * std::sin(angle / kDegPerRad) * kTableStepDeg / kDegPerRad;
    for (std::size_t c = 0; c < 3; ++c) {
      table_[c][i] = ring[c];
      energy[c] += ring[c] * solid_angle;
    }
  }
  // Unit energy per channel again: the halo's light is taken from the source's own pixel channel by
  // channel, so each channel's ring must hold what it takes (into_gamut added white light).
  for (std::size_t c = 0; c < 3; ++c)
    for (double& value : table_[c]) value /= energy[c];
  // The 380 and 780 nm ends carry almost nothing: the table ends where every channel is below 1e-9
  // of its peak, so the display kernel reaches no further than the ring's light does.
  double peak = 0.0;
  for (const auto& channel : table_) peak = std::max(peak, *std::max_element(channel.begin(), channel.end()));
  std::size_t first = count, last = 0;
  for (std::size_t i = 0; i < count; ++i)
    for (const auto& channel : table_)
      if (channel[i] > 1e-9 * peak) first = std::min(first, i), last = std::max(last, i);
  first = first > 0 ? first - 1 : 0;
  last = std::min(count - 1, last + 1);
  for (auto& channel : table_)
    channel = std::vector<double>(channel.begin() + static_cast<std::ptrdiff_t>(first),
                                  channel.begin() + static_cast<std::ptrdiff_t>(last) + 1);
  table_start_deg_ = from + static_cast<double>(first) * kTableStepDeg;
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
  // The ring is the same at the eight offsets (+-dx, +-dy) and (+-dy, +-dx): a pixel's subsamples
  // are the mirror images of its mirror's (x -> -x takes sample a to n - 1 - a) and the kernel
  // depends on the distance alone. So each integral is made once, for 0 <= dy <= dx, and written to
  // all eight: an eighth of the work, the kernel symmetric to the last bit. Pixels wholly inside or
  // outside the ring's angles get nothing.
  std::vector<std::pair<int, int>> offsets;
  for (int dy = 0; dy <= half; ++dy)
    for (int dx = dy; dx <= half; ++dx) {
      const double r_px = std::hypot(dx, dy);
      const double near_deg = std::atan(std::max(0.0, r_px - 0.7072) * pitch / d) * kDegPerRad;
      const double far_deg = std::atan((r_px + 0.7072) * pitch / d) * kDegPerRad;
      if (far_deg >= halo.inner_deg() && near_deg <= halo.outer_deg()) offsets.emplace_back(dx, dy);
    }
  parallel_chunks(static_cast<int>(offsets.size()), threads, [&](int first, int last) {
    for (int i = first; i < last; ++i) {
      const auto [dx, dy] = offsets[static_cast<std::size_t>(i)];
      std::array<double, 3> sum{0.0, 0.0, 0.0};
      for (int b = 0; b < n; ++b)
        for (int a = 0; a < n; ++a) {
          const double x = (dx - 0.5 + (a + 0.5) / n) * pitch, y = (dy - 0.5 + (b + 0.5) / n) * pitch;
          const double r2 = x * x + y * y;
          const double angle_deg = std::atan(std::sqrt(r2) / d) * kDegPerRad;
          const double solid_angle = d * sub_area / std::pow(d * d + r2, 1.5);
          for (int c = 0; c < 3; ++c) sum[static_cast<std::size_t>(c)] += halo.per_sr(angle_deg, c) * solid_angle;
        }
      // Each offset's eight images are its own (an offset on an axis or a diagonal writes some twice).
      for (const auto& [x, y] : {std::pair{dx, dy}, std::pair{-dx, dy}, std::pair{dx, -dy}, std::pair{-dx, -dy},
                                std::pair{dy, dx}, std::pair{-dy, dx}, std::pair{dy, -dx}, std::pair{-dy, -dx}}) {
        const std::size_t index = static_cast<std::size_t>(y + half) * kernel.width_px() + static_cast<std::size_t>(x + half);
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
  ring(source_energy);
  for (std::size_t i = 0; i < glared_energy.rgba.size(); i += 4)
    for (std::size_t c = 0; c < 3; ++c)
      glared_energy.rgba[i + c] += static_cast<float>(
          halo_energy * (static_cast<double>(last_ring_.rgba[i + c]) - static_cast<double>(source_energy.rgba[i + c])));
}

const ImageRGBA& LenticularHaloGlare::ring(const ImageRGBA& source_energy, std::uint64_t source_token) {
  if (kept_ && source_token != 0 && source_token == kept_token_) return last_ring_;
  const bool same = kept_ && same_pixel_bits(last_source_, source_energy);
  if (!same) {
    kept_ = false;  // until the new ring is in place
    convolution_->convolve(source_energy, last_ring_);
    last_source_ = source_energy;
    kept_ = true;
    ++convolutions_computed_;
  }
  kept_token_ = source_token;
  return last_ring_;
}

}  // namespace glarelab
