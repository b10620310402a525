#include "glare/wave/luidolt_kernel.h"

#include <algorithm>
#include <cmath>
#include <complex>
#include <numbers>
#include <sstream>

#include "core/fft_size.h"
#include "core/parallel_for.h"
#include "core/random.h"
#include "glare/cpu/psf.h"
#include "glare/eye/eye_random_channels.h"
#include "glare/wave/cie_cmf.h"
#include "glare/wave/fresnel.h"
#include "glare/wave/spectral_accumulation.h"

namespace glarelab {
namespace {

constexpr const char* kSubsystem = "glare/wave/luidolt_kernel";

void check_options(const LuidoltKernelOptions& o) {
  auto fail = [](const std::string& what) { throw std::invalid_argument(std::string(kSubsystem) + ": " + what); };
  if (o.particle_count < 0) fail("particle_count must be >= 0");
  if (!(o.particle_diameter_mm > 0.0)) fail("particle_diameter_mm must be > 0");
  if (!(o.wavelength_nm > 0.0)) fail("wavelength_nm must be > 0");
  if (!(o.distance_mm > 0.0)) fail("distance_mm must be > 0");
  if (!(o.aperture_width_mm > 0.0)) fail("aperture_width_mm must be > 0");
  if (o.wavelength_count < 2) fail("wavelength_count (k + 1 of Eq. 5.13) must be >= 2");
  if (o.grid_px < 2 || o.grid_px % 2 != 0) fail("grid_px must be even and >= 2");
}

// The smallest even 2,3,5-smooth size >= n (a PSF is centred on pixel N/2 of an even grid).
int even_smooth_size(double n) {
  int size = smooth_fft_size(static_cast<int>(std::ceil(n)));
  while (size % 2 != 0) size = smooth_fft_size(size + 1);
  return size;
}

// Eq. 5.6's coefficient c of pi c r^2: 1 / (lambda d), in 1/m^2.
double fresnel_coefficient_per_m2(const LuidoltKernelOptions& o) {
  return 1.0 / (o.wavelength_nm * 1e-9 * o.distance_mm * 1e-3);
}

double bilinear(const std::vector<double>& image, int n, double x, double y) {
  const double fx0 = std::floor(x), fy0 = std::floor(y);
  const int x0 = static_cast<int>(fx0), y0 = static_cast<int>(fy0);
  const double fx = x - fx0, fy = y - fy0;
  auto value = [&](int xi, int yi) {
    if (xi < 0 || yi < 0 || xi >= n || yi >= n) return 0.0;
    return image[static_cast<std::size_t>(yi) * n + xi];
  };
  return (1 - fy) * ((1 - fx) * value(x0, y0) + fx * value(x0 + 1, y0)) +
         fy * ((1 - fx) * value(x0, y0 + 1) + fx * value(x0 + 1, y0 + 1));
}

}  // namespace

LuidoltSampling luidolt_sampling(double pupil_diameter_mm, const LuidoltKernelOptions& options) {
  check_options(options);
  const double width = options.aperture_width_mm;
  const PhaseSamplingReport report = check_phase_sampling(fresnel_coefficient_per_m2(options), 0.5 * pupil_diameter_mm,
                                                          width / options.grid_px, width);
  LuidoltSampling sampling;
  sampling.max_pixel_mm = report.max_pixel_mm;
  sampling.edge_phase_step_rad = report.max_phase_step_rad;
  sampling.aliased = report.aliased;
  sampling.required_grid_px = even_smooth_size(report.required_grid_px_exact);
  return sampling;
}

std::vector<LuidoltParticle> luidolt_particles(std::uint64_t seed, const LuidoltKernelOptions& options) {
  check_options(options);
  const CounterRandom random(seed, RandomStream::eye_model);
  std::vector<LuidoltParticle> particles;
  particles.reserve(static_cast<std::size_t>(options.particle_count));
  for (int i = 0; i < options.particle_count; ++i) {
    const auto index = static_cast<std::uint64_t>(i);
    particles.push_back({(random.uniform(index, eye_sub_index(EyeChannel::luidolt_particles, 0)) - 0.5) * options.aperture_width_mm,
                         (random.uniform(index, eye_sub_index(EyeChannel::luidolt_particles, 1)) - 0.5) * options.aperture_width_mm});
  }
  return particles;
}

std::vector<double> luidolt_aperture_mask(const std::vector<LuidoltParticle>& particles, double pupil_diameter_mm,
                                          int grid_px, const LuidoltKernelOptions& options) {
  const int n = grid_px;
  const double dx = options.aperture_width_mm / n, half = 0.5 * options.aperture_width_mm;
  auto centre_mm = [&](int i) { return (i + 0.5) * dx - half; };
  std::vector<double> mask(static_cast<std::size_t>(n) * n, 0.0);
  const double pupil_r2 = 0.25 * pupil_diameter_mm * pupil_diameter_mm;
  parallel_chunks(n, 0, [&](int first, int last) {
    for (int y = first; y < last; ++y)
      for (int x = 0; x < n; ++x) {
        const double px = centre_mm(x), py = centre_mm(y);
        if (px * px + py * py <= pupil_r2) mask[static_cast<std::size_t>(y) * n + x] = 1.0;
      }
  });
  // P: each dot clears the samples whose centres it covers.
  const double particle_r = 0.5 * options.particle_diameter_mm, particle_r2 = particle_r * particle_r;
  for (const LuidoltParticle& p : particles) {
    const int x0 = std::max(0, static_cast<int>(std::floor((p.x_mm - particle_r + half) / dx)));
    const int x1 = std::min(n - 1, static_cast<int>(std::floor((p.x_mm + particle_r + half) / dx)));
    const int y0 = std::max(0, static_cast<int>(std::floor((p.y_mm - particle_r + half) / dx)));
    const int y1 = std::min(n - 1, static_cast<int>(std::floor((p.y_mm + particle_r + half) / dx)));
    for (int y = y0; y <= y1; ++y)
      for (int x = x0; x <= x1; ++x) {
        const double ex = centre_mm(x) - p.x_mm, ey = centre_mm(y) - p.y_mm;
        if (ex * ex + ey * ey <= particle_r2) mask[static_cast<std::size_t>(y) * n + x] = 0.0;
      }
  }
  return mask;
}

std::vector<double> luidolt_spectral_xyz(const std::vector<double>& monochromatic, int grid_px, double wavelength_nm,
                                         int wavelength_count) {
  const int n = grid_px;
  const std::size_t plane = static_cast<std::size_t>(n) * n;
  if (monochromatic.size() != plane) throw std::invalid_argument(std::string(kSubsystem) + ": M is not N x N");
  if (wavelength_count < 2) throw std::invalid_argument(std::string(kSubsystem) + ": Eq. 5.13 needs k >= 1");
  const int k = wavelength_count - 1;
  std::vector<double> xyz(3 * plane, 0.0);
  const double centre = n / 2;
  for (int i = 0; i <= k; ++i) {
    const double phi_nm = 380.0 + static_cast<double>(i) / k * (770.0 - 380.0);  // Eq. 5.13
    const Xyz cmf = cie1931_cmf(phi_nm);
    const double scale = wavelength_nm / phi_nm, share = 1.0 / (k + 1);
    // Eq. 5.12: S(x) += XYZ(phi) M(x lambda / phi) / (k + 1); rows on threads, each row its own.
    parallel_chunks(n, 0, [&](int first, int last) {
      for (int y = first; y < last; ++y) {
        const double sy = (y - centre) * scale + centre;
        for (int x = 0; x < n; ++x) {
          const double m = bilinear(monochromatic, n, (x - centre) * scale + centre, sy) * share;
          if (m == 0.0) continue;
          const std::size_t at = static_cast<std::size_t>(y) * n + x;
          xyz[at] += cmf.x * m;
          xyz[plane + at] += cmf.y * m;
          xyz[2 * plane + at] += cmf.z * m;
        }
      }
    });
  }
  return xyz;
}

std::string luidolt_description(const LuidoltKernelOptions& options) {
  std::ostringstream out;
  out << options.particle_count << " static particles of " << options.particle_diameter_mm << " mm over a "
      << options.aperture_width_mm << " mm texture, the Fresnel term at " << options.wavelength_nm << " nm and d = "
      << options.distance_mm << " mm (Eq. 5.6) on a grid of at least " << options.grid_px
      << " px, enlarged for each pupil until the term's step at the pupil's edge is below pi, " << options.wavelength_count
      << " wavelengths (Eqs. 5.12-5.13), the unscattered light in a bright centre pixel";
  return out.str();
}

LuidoltKernel luidolt_kernel(double pupil_diameter_mm, std::uint64_t seed, const LuidoltKernelOptions& options) {
  check_options(options);
  if (!(pupil_diameter_mm > 0.0 && pupil_diameter_mm <= options.aperture_width_mm)) {
    std::ostringstream out;
    out << kSubsystem << ": pupil " << pupil_diameter_mm << " mm is outside (0, " << options.aperture_width_mm
        << "] mm, the texture's side";
    throw std::invalid_argument(out.str());
  }
  LuidoltKernel kernel;
  kernel.pupil_diameter_mm = pupil_diameter_mm;
  const LuidoltSampling sampling = luidolt_sampling(pupil_diameter_mm, options);
  int n = options.grid_px;
  if (sampling.aliased) {
    std::ostringstream why;
    why << "Eq. 5.6's Fresnel term exp(i pi r^2 / (lambda d)) at " << options.wavelength_nm << " nm and d = "
        << options.distance_mm << " mm steps " << sampling.edge_phase_step_rad << " rad between samples at the "
        << pupil_diameter_mm << " mm pupil's edge on " << options.grid_px << " px over " << options.aperture_width_mm
        << " mm (needs < pi: pixels below " << sampling.max_pixel_mm * 1e3 << " um, a grid of at least "
        << sampling.required_grid_px << " px)";
    if (!options.enlarge_grid) throw LuidoltSamplingError(std::string(kSubsystem) + ": " + why.str());
    if (sampling.required_grid_px > options.largest_grid_px)
      throw LuidoltSamplingError(std::string(kSubsystem) + ": " + why.str() + ", past the largest grid, " +
                                 std::to_string(options.largest_grid_px) + " px");
    n = sampling.required_grid_px;
    kernel.sampling_note = "grid enlarged from " + std::to_string(options.grid_px) + " to " + std::to_string(n) +
                           " px: " + why.str();
  }
  kernel.grid_px = n;

  // Eq. 5.7: L = P F A, with P A the binary mask and F Eq. 5.6 at each sample's radius (metres).
  const std::vector<double> mask = luidolt_aperture_mask(luidolt_particles(seed, options), pupil_diameter_mm, n, options);
  const double c = fresnel_coefficient_per_m2(options), dx_m = options.aperture_width_mm * 1e-3 / n;
  const double half_m = 0.5 * options.aperture_width_mm * 1e-3;
  const double pupil_r_m = 0.5 * pupil_diameter_mm * 1e-3;
  std::vector<std::complex<double>> field(mask.size());
  double open = 0.0;
  for (int y = 0; y < n; ++y)
    for (int x = 0; x < n; ++x) {
      const std::size_t at = static_cast<std::size_t>(y) * n + x;
      const double px = (x + 0.5) * dx_m - half_m, py = (y + 0.5) * dx_m - half_m, r2 = px * px + py * py;
      if (r2 <= pupil_r_m * pupil_r_m) kernel.pupil_pixels += 1.0;
      if (mask[at] == 0.0) continue;
      open += 1.0;
      field[at] = std::polar(1.0, quadratic_phase_rad(c, r2));
    }
  if (open == 0.0) throw ClosedApertureError(std::string(kSubsystem) + ": the particles cover the whole pupil");
  kernel.covered_fraction = 1.0 - open / kernel.pupil_pixels;
  kernel.centre_share = 1.0 - kernel.covered_fraction;

  // Eqs. 5.10-5.11: M = |FFT(L) / N|^2 / (lambda d)^2, DC at (N/2, N/2).
  std::vector<double> m = shifted_power_spectrum(std::move(field), n, FftPrecision::float64);
  const double lambda_d_m2 = options.wavelength_nm * 1e-9 * options.distance_mm * 1e-3;
  const double to_m = 1.0 / (static_cast<double>(n) * n * lambda_d_m2 * lambda_d_m2);
  for (double& value : m) {
    value *= to_m;
    kernel.monochromatic_sum_per_m2 += value;
  }
  const std::size_t dc = static_cast<std::size_t>(n / 2) * n + n / 2;
  kernel.monochromatic_dc_per_m2 = m[dc];
  m[dc] = 0.0;  // Eq. 5.10: pixel (0, 0) belongs to the bright centre

  const double degrees_per_pixel = psf_degrees_per_pixel(options.wavelength_nm, options.aperture_width_mm);
  if (kernel.covered_fraction == 0.0) {
    // Nothing scattered: the scattered part has weight 0, and the kernel is its bright centre alone.
    kernel.psf.size_px = n;
    kernel.psf.channels = 3;
    kernel.psf.degrees_per_pixel = degrees_per_pixel;
    kernel.psf.values.assign(3 * static_cast<std::size_t>(n) * n, 0.0);
    for (int ch = 0; ch < 3; ++ch) kernel.psf.at(ch, n / 2, n / 2) = 1.0;
    return kernel;
  }
  XyzPlanes sum(n);
  sum.values = luidolt_spectral_xyz(m, n, options.wavelength_nm, options.wavelength_count);
  m.clear();
  m.shrink_to_fit();
  SpectralPsfResult rgb = rec709_psf_from_xyz(sum, degrees_per_pixel, kSubsystem);
  for (int ch = 0; ch < 3; ++ch) kernel.clamped_negative_fraction[ch] = rgb.clamped_negative_fraction[ch];
  kernel.psf = std::move(rgb.psf);
  // The scattered part holds the covered fraction, the added centre the rest (section 6.3.2).
  for (double& value : kernel.psf.values) value *= kernel.covered_fraction;
  for (int ch = 0; ch < 3; ++ch) kernel.psf.at(ch, n / 2, n / 2) += kernel.centre_share;
  return kernel;
}

}  // namespace glarelab
