#include "glare/gl/psf.h"

#include <algorithm>
#include <cmath>
#include <complex>
#include <numbers>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/gl/read_back.h"
#include "glare/refraction/astigmatic_phase.h"
#include "glare/refraction/chromatic_eye.h"
#include "glare/wave/fresnel.h"
#include "glare/wave/cie_cmf.h"
#include "glare/gl/cross_phase_turns.h"
#include "core/gl/shader_program.h"

namespace glarelab::gl {
namespace {

constexpr GLuint kTile = 8;          // local size of the 2D PSF shaders
constexpr GLuint kReduceSpan = 512;  // values per workgroup in sum_reduce.comp
constexpr GLuint kNormaliseGroup = 256;
// At most this many groups per dispatch (524 288 invocations, plenty to fill a GPU): OpenGL
// guarantees only 65535 per dimension, and a 4096^2 channel would need 65536; psf_normalise.comp
// strides over the rest (from N = 1024 on, so the tests at 1024 and 4096 run the loop).
constexpr GLuint kMaxNormaliseGroups = 2048;

void check_wavelength(double wavelength_nm) {
  if (!(wavelength_nm > 0.0) || !std::isfinite(wavelength_nm))
    throw std::invalid_argument("GL PSF: wavelength " + std::to_string(wavelength_nm) + " nm is not positive");
}

// The sampling check compute_monochromatic_psf (glare/cpu/psf.h) makes for a power error: glare/wave/fresnel.h's for
// a spherical error, the strongest principal meridian's (glare/refraction/astigmatic_phase.h) otherwise.
PhaseSamplingReport power_error_sampling(const DioptricPower& error, double wavelength_nm, double pupil_radius_mm,
                                         double pixel_mm, double width_mm) {
  if (error.xy() != 0.0 || error.xx() != error.yy())
    return check_power_error_sampling(error, wavelength_nm, pupil_radius_mm, pixel_mm, width_mm);
  return check_phase_sampling(phase_coefficient_per_m2(PhaseForm::defocus, wavelength_nm, error.xx()), pupil_radius_mm,
                              pixel_mm, width_mm);
}

GLuint tiles(int extent) { return (static_cast<GLuint>(extent) + kTile - 1) / kTile; }

Buffer storage(std::size_t bytes) {
  Buffer buffer = create_buffer();
  glNamedBufferStorage(buffer.get(), static_cast<GLsizeiptr>(bytes), nullptr, GL_DYNAMIC_STORAGE_BIT);
  return buffer;
}

}  // namespace

GlPsf::GlPsf(int size_px, double aperture_width_mm, int supersampling)
    : size_px_(size_px),
      aperture_((is_power_of_two_fft_length(size_px)
                     ? size_px
                     : throw std::invalid_argument("GL PSF: grid size " + std::to_string(size_px) +
                                                   " is not a power of two from 16 to 4096")),
                aperture_width_mm, supersampling),
      fft_(size_px, size_px) {
  load_program_ = build_program({"glare/shaders/psf_load_aperture.comp"});
  astigmatic_load_program_ = build_program({"glare/shaders/psf_load_aperture_astigmatic.comp"});
  power_program_ = build_program({"glare/shaders/psf_power_shift.comp"});
  reduce_program_ = build_program({"glare/shaders/sum_reduce.comp"});
  normalise_program_ = build_program({"glare/shaders/psf_normalise.comp"});
  spectral_program_ = build_program({"glare/shaders/psf_spectral.comp"});
  chromatic_program_ = build_program({"glare/shaders/psf_chromatic_accumulate.comp"});
  clamp_program_ = build_program({"glare/shaders/psf_clamp_negative.comp"});
  const std::size_t count = static_cast<std::size_t>(size_px) * size_px;
  // A slot of phase factors starts where a storage buffer binding may (glBindBufferRange).
  GLint alignment = 0;
  glGetIntegerv(GL_SHADER_STORAGE_BUFFER_OFFSET_ALIGNMENT, &alignment);
  const std::size_t factor_bytes = static_cast<std::size_t>(size_px) * 2 * sizeof(float);
  const std::size_t step = static_cast<std::size_t>(std::max(alignment, 1));
  phase_slot_bytes_ = (factor_bytes + step - 1) / step * step;
  const std::vector<glm::vec2> table = cross_phase_table();
  cross_table_ = storage(table.size() * sizeof(table[0]));
  glNamedBufferSubData(cross_table_.get(), 0, static_cast<GLsizeiptr>(table.size() * sizeof(table[0])), table.data());
  power_ = storage(count * sizeof(float));
  spectral_ = storage(3 * count * sizeof(float));
  const std::size_t partials = 3 * ((count + kReduceSpan - 1) / kReduceSpan);
  partial_a_ = storage(partials * sizeof(float));
  partial_b_ = storage(partials * sizeof(float));
  power_sums_ = storage(sizeof(float));
  spectral_sums_ = storage(3 * sizeof(float));
  weights_ = create_buffer();
  check_gl_error("GL PSF: creating buffers and programs");
}

double GlPsf::degrees_per_pixel(double wavelength_nm) const {
  // Fraunhofer: one PSF pixel is one frequency step 1 / (N dx) of the aperture grid, an angle of
  // lambda / (N dx) radians (Goodman 2005, section 4.3).
  const double wavelength_mm = wavelength_nm * 1e-6;
  return wavelength_mm / (size_px_ * aperture_.pixel_size_mm()) * 180.0 / std::numbers::pi;
}

void GlPsf::normalise(GLuint values, int channels) {
  const GLuint reduce = reduce_program_.get();
  glUseProgram(reduce);
  GLuint count = static_cast<GLuint>(size_px_) * static_cast<GLuint>(size_px_);
  const GLuint per_channel = count;
  GLuint source = values;
  bool to_a = true;
  while (count > 1) {
    const GLuint groups = (count + kReduceSpan - 1) / kReduceSpan;
    const GLuint destination = to_a ? partial_a_.get() : partial_b_.get();
    glUniform1ui(glGetUniformLocation(reduce, "uCount"), count);
    glUniform1ui(glGetUniformLocation(reduce, "uGroupsPerChannel"), groups);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, source);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 1, destination);
    glDispatchCompute(groups, static_cast<GLuint>(channels), 1);
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
    source = destination;
    to_a = !to_a;
    count = groups;
  }
  // A closed eye (lids over the whole pupil) sums to 0: psf_normalise.comp leaves such a channel as
  // it is, and read() refuses it by type, as the CPU does (glare/wave/psf.h). The sums are kept on the
  // GPU beside the result rather than read back here, so a PSF costs one round trip, not three.
  glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
  glCopyNamedBufferSubData(source, values == power_.get() ? power_sums_.get() : spectral_sums_.get(), 0, 0,
                           static_cast<GLsizeiptr>(channels * sizeof(float)));
  const GLuint normalise_program = normalise_program_.get();
  glUseProgram(normalise_program);
  glUniform1ui(glGetUniformLocation(normalise_program, "uCount"), per_channel);
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, values);
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 1, source);
  glDispatchCompute(std::min((per_channel + kNormaliseGroup - 1) / kNormaliseGroup, kMaxNormaliseGroups),
                    static_cast<GLuint>(channels), 1);
  glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
}

void GlPsf::load_field(const ApertureGeometry& geometry, double wavelength_nm) {
  check_wavelength(wavelength_nm);  // before anything is drawn
  aperture_.draw(geometry);
  apply_phase(geometry.total_power_error(), wavelength_nm);
}

void GlPsf::apply_phase(const DioptricPower& error, double wavelength_nm) {
  check_wavelength(wavelength_nm);
  upload_phases({{error, wavelength_nm}});
  load_with_phase(error, wavelength_nm, 0);
}

// The x^2 and y^2 terms of phi = (pi / lambda)(E_xx x^2 + 2 E_xy x y + E_yy y^2), with E in 1/m,
// lengths in m and lambda in m, written for x in mm and lambda in nm: pi E x_mm^2 1e3 / lambda_nm.
// Per axis: exp(i a x^2) (see psf_load_aperture.comp). For a spherical error both factors are
// glare/wave/fresnel.h's defocus phase of E_xx = E_yy, computed as before the error had a cylinder.
//
// Every phase a PSF needs goes into one new buffer, made with its data and never written again:
// slot k holds the per-column factors at 2 k slot_bytes and the per-row ones at (2 k + 1)
// slot_bytes. A buffer rewritten in place between the dispatches that read it (glNamedBufferSubData
// per wavelength) gave wrong PSFs on an NVIDIA H200 (driver 580.159.04): the chromatic PSF's
// wavelengths read one another's phases, 0.8 to 140 times its peak off, and a glFinish after each
// wavelength made it right, a glMemoryBarrier did not (docs/PERFORMANCE.md, the H200 of 30 November).
void GlPsf::upload_phases(const std::vector<std::pair<DioptricPower, double>>& phases) {
  const std::size_t floats_per_slot = phase_slot_bytes_ / sizeof(float);
  std::vector<float> values(2 * phases.size() * floats_per_slot, 0.0f);
  const double dx_mm = aperture_.pixel_size_mm();
  for (std::size_t k = 0; k < phases.size(); ++k) {
    const auto& [error, wavelength_nm] = phases[k];
    const double a_per_mm2[2] = {std::numbers::pi * error.xx() * 1e3 / wavelength_nm,
                                 std::numbers::pi * error.yy() * 1e3 / wavelength_nm};
    for (int axis = 0; axis < 2; ++axis) {
      float* factors = values.data() + (2 * k + static_cast<std::size_t>(axis)) * floats_per_slot;
      for (int i = 0; i < size_px_; ++i) {
        // Pixel centres as in glare/eye/aperture_raster.h: column i at x = (i - N/2) dx, row j at
        // y = (N/2 - j) dx, whose square is the same function of the index.
        const double x_mm = (i - size_px_ / 2) * dx_mm;
        const std::complex<float> factor(std::polar(1.0, a_per_mm2[axis] * x_mm * x_mm));
        factors[2 * i] = factor.real();
        factors[2 * i + 1] = factor.imag();
      }
    }
  }
  phases_ = create_buffer();
  glNamedBufferStorage(phases_.get(), static_cast<GLsizeiptr>(values.size() * sizeof(float)), values.data(), 0);
}

void GlPsf::load_with_phase(const DioptricPower& error, double wavelength_nm, std::size_t slot) {
  // The cross term 2 pi E_xy x y / lambda only where there is one (an oblique cylinder): without it
  // the field is the separable product alone, from the same shader as a spherical defocus.
  const bool cross = error.xy() != 0.0;
  const GLuint load = cross ? astigmatic_load_program_.get() : load_program_.get();
  glUseProgram(load);
  glUniform1i(glGetUniformLocation(load, "uSize"), size_px_);
  if (cross) {
    const FixedPointTurns turns =
        fixed_point_fraction(cross_phase_turns_per_index(error.xy(), aperture_.pixel_size_mm(), wavelength_nm));
    glUniform2ui(glGetUniformLocation(load, "uCrossTurns"), turns.high, turns.low);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 3, cross_table_.get());
  }
  const auto factor_bytes = static_cast<GLsizeiptr>(size_px_) * 2 * static_cast<GLsizeiptr>(sizeof(float));
  const auto offset = static_cast<GLintptr>(2 * slot * phase_slot_bytes_);
  glBindImageTexture(0, aperture_.texture(), 0, GL_FALSE, 0, GL_READ_ONLY, GL_R32F);
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, fft_.data());
  glBindBufferRange(GL_SHADER_STORAGE_BUFFER, 1, phases_.get(), offset, factor_bytes);
  glBindBufferRange(GL_SHADER_STORAGE_BUFFER, 2, phases_.get(), offset + static_cast<GLintptr>(phase_slot_bytes_),
                    factor_bytes);
  glDispatchCompute(tiles(size_px_), tiles(size_px_), 1);
  glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
  glUseProgram(0);
  check_gl_error("GL PSF: loading the pupil function");
}

std::vector<std::complex<float>> GlPsf::read_field() const { return fft_.download(); }

void GlPsf::run_monochromatic(const ApertureGeometry& geometry, double wavelength_nm) {
  load_field(geometry, wavelength_nm);

  fft_.transform(FftDirection::forward);

  const GLuint power = power_program_.get();
  glUseProgram(power);
  glUniform1i(glGetUniformLocation(power, "uSize"), size_px_);
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, fft_.data());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 1, power_.get());
  glDispatchCompute(tiles(size_px_), tiles(size_px_), 1);
  glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);

  normalise(power_.get(), 1);
  glUseProgram(0);
  check_gl_error("GL PSF: monochromatic");
}

void GlPsf::run_spectral(const ApertureGeometry& geometry, int wavelength_count, double reference_wavelength_nm) {
  const std::vector<SpectralSample> samples = spectral_samples(wavelength_count);
  run_monochromatic(geometry, reference_wavelength_nm);
  std::vector<float> weights;
  for (const SpectralSample& sample : samples)
    weights.insert(weights.end(), {static_cast<float>(sample.weight.r), static_cast<float>(sample.weight.g),
                                   static_cast<float>(sample.weight.b),
                                   static_cast<float>(reference_wavelength_nm / sample.wavelength_nm)});
  glNamedBufferData(weights_.get(), static_cast<GLsizeiptr>(weights.size() * sizeof(float)), weights.data(), GL_DYNAMIC_DRAW);

  const GLuint spectral = spectral_program_.get();
  glUseProgram(spectral);
  glUniform1i(glGetUniformLocation(spectral, "uSize"), size_px_);
  glUniform1i(glGetUniformLocation(spectral, "uWavelengthCount"), wavelength_count);
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, power_.get());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 1, spectral_.get());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 2, weights_.get());
  glDispatchCompute(tiles(size_px_), tiles(size_px_), 1);
  glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
  normalise(spectral_.get(), 3);
  glUseProgram(0);
  check_gl_error("GL PSF: spectral");
}

void GlPsf::run_chromatic(const ApertureGeometry& geometry, int wavelength_count, double reference_wavelength_nm) {
  // Every refusal before anything is drawn: the samples (n >= 1) and the LCA at the reference.
  check_wavelength(reference_wavelength_nm);
  const std::vector<SpectralSample> samples = spectral_samples(wavelength_count);
  std::vector<double> excess_dioptres;
  for (const SpectralSample& sample : samples)
    excess_dioptres.push_back(chromatic_power_excess_dioptres(sample.wavelength_nm, reference_wavelength_nm));

  // The aperture does not depend on wavelength: drawn once, each wavelength only re-applies its phase.
  aperture_.draw(geometry);
  const DioptricPower reference_error = geometry.total_power_error();
  const GLuint count = static_cast<GLuint>(size_px_) * static_cast<GLuint>(size_px_);
  const float zero = 0.0f;
  glClearNamedBufferData(spectral_.get(), GL_R32F, GL_RED, GL_FLOAT, &zero);
  chromatic_warning_.clear();
  chromatic_aliased_ = 0;
  double worst_step_rad = 0.0;
  const double pupil_radius_mm = 0.5 * geometry.pupil_diameter_mm, pixel_mm = aperture_.pixel_size_mm();
  // glare/wave/chromatic_psf.cpp's chromatic_power_error: E_ref + [LCA(lambda) - LCA(lambda_ref)] I.
  std::vector<std::pair<DioptricPower, double>> phases;
  for (std::size_t i = 0; i < samples.size(); ++i)
    phases.emplace_back(reference_error + DioptricPower::spherical(excess_dioptres[i]), samples[i].wavelength_nm);
  upload_phases(phases);
  for (std::size_t i = 0; i < samples.size(); ++i) {
    const SpectralSample& sample = samples[i];
    const DioptricPower& error = phases[i].first;
    const PhaseSamplingReport sampling =
        power_error_sampling(error, sample.wavelength_nm, pupil_radius_mm, pixel_mm, size_px_ * pixel_mm);
    if (sampling.aliased) {
      ++chromatic_aliased_;
      const double step_rad =
          check_power_error_sampling(error, sample.wavelength_nm, pupil_radius_mm, pixel_mm, size_px_ * pixel_mm)
              .max_phase_step_rad;
      if (step_rad > worst_step_rad) {
        worst_step_rad = step_rad;
        std::ostringstream where;
        where << " (at " << sample.wavelength_nm << " nm)";
        chromatic_warning_ = sampling.warning + where.str();
      }
    }
    load_with_phase(error, sample.wavelength_nm, i);
    fft_.transform(FftDirection::forward);
    const double scale = reference_wavelength_nm / sample.wavelength_nm;
    const double jacobian = scale * scale;
    const GLuint accumulate = chromatic_program_.get();
    glUseProgram(accumulate);
    glUniform1i(glGetUniformLocation(accumulate, "uSize"), size_px_);
    glUniform1f(glGetUniformLocation(accumulate, "uScale"), static_cast<float>(scale));
    glUniform3f(glGetUniformLocation(accumulate, "uWeight"), static_cast<float>(jacobian * sample.weight.r),
                static_cast<float>(jacobian * sample.weight.g), static_cast<float>(jacobian * sample.weight.b));
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, fft_.data());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 1, spectral_.get());
    glDispatchCompute(tiles(size_px_), tiles(size_px_), 1);
    // The next wavelength's load writes the FFT buffer this pass reads.
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
  }
  const GLuint clamp = clamp_program_.get();
  glUseProgram(clamp);
  glUniform1ui(glGetUniformLocation(clamp, "uCount"), 3 * count);
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, spectral_.get());
  glDispatchCompute(std::min((3 * count + kNormaliseGroup - 1) / kNormaliseGroup, kMaxNormaliseGroups), 1, 1);
  glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
  normalise(spectral_.get(), 3);
  glUseProgram(0);
  check_gl_error("GL PSF: chromatic");
}

Psf GlPsf::read(int channels, double wavelength_nm) const {
  glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
  const std::size_t count = static_cast<std::size_t>(channels) * size_px_ * size_px_;
  std::vector<float> values(count);
  read_back_buffer(result_buffer(channels), 0, count * sizeof(float), values.data(), ReadBackKind::kernel);
  std::vector<float> sums(static_cast<std::size_t>(channels));
  read_back_buffer(channels == 1 ? power_sums_.get() : spectral_sums_.get(), 0, sums.size() * sizeof(float),
                   sums.data(), ReadBackKind::reduction);
  check_gl_error("GL PSF: reading back");
  for (const float sum : sums)
    if (!(sum > 0.0f))
      throw ClosedApertureError("GL PSF: the aperture transmits no light (pupil outside the grid or fully blocked)");
  Psf psf;
  psf.size_px = size_px_;
  psf.channels = channels;
  psf.degrees_per_pixel = degrees_per_pixel(wavelength_nm);
  psf.values.assign(values.begin(), values.end());
  return psf;
}

Psf GlPsf::monochromatic(const ApertureGeometry& geometry, double wavelength_nm) {
  run_monochromatic(geometry, wavelength_nm);
  return read(1, wavelength_nm);
}

Psf GlPsf::spectral(const ApertureGeometry& geometry, int wavelength_count, double reference_wavelength_nm) {
  run_spectral(geometry, wavelength_count, reference_wavelength_nm);
  return read(3, reference_wavelength_nm);
}

Psf GlPsf::chromatic(const ApertureGeometry& geometry, int wavelength_count, double reference_wavelength_nm) {
  run_chromatic(geometry, wavelength_count, reference_wavelength_nm);
  return read(3, reference_wavelength_nm);
}

}  // namespace glarelab::gl
