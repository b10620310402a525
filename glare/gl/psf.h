#pragma once
// The GPU point-spread function (Ritschel et al. 2009, sections 4-5) from an ApertureGeometry:
// aperture (glare/gl/aperture.h) times the pupil phase of the eye's power error (defocus and,
// for an astigmatic error, the sphero-cylindrical phase of glare/refraction/astigmatic_phase.h), GL FFT (glare/gl/fft.h),
// |F|^2 with the zero frequency at pixel (N/2, N/2), each channel normalised to sum 1 by a pairwise
// reduction on the GPU. Angular pixel size in the Fraunhofer limit: lambda / (N dx) radians.
// The spectral PSF resamples the reference-wavelength PSF in angle for n wavelengths over
// 380-770 nm and weights them by the CIE 1931 CMFs in linear Rec.709 (glare/wave/cie_cmf.h); the
// chromatic PSF gives every wavelength its own FFT with the eye's longitudinal chromatic aberration
// (glare/wave/chromatic_psf.h's operator on the GPU).
// Requires a current OpenGL 4.5 context; not thread-safe.
#include <complex>
#include <string>
#include <utility>
#include <vector>

#include "glare/eye/aperture_geometry.h"
#include "glare/refraction/dioptric_power.h"
#include "glare/gl/aperture.h"
#include "glare/gl/fft.h"
#include "glare/wave/psf.h"

namespace glarelab::gl {

class GlPsf {
 public:
  // size_px: a power of two 16..4096 (is_power_of_two_fft_length); aperture_width_mm: the side of the
  // pupil-plane grid. Throws std::invalid_argument("GL PSF: ...") / ("GL aperture: ...").
  GlPsf(int size_px, double aperture_width_mm, int supersampling = 2);

  // The pupil function the FFT takes: the aperture of `geometry` times exp(i phi), phi that of
  // geometry.total_power_error() (glare/refraction/astigmatic_phase.h), in the FFT's buffer. A power error
  // without an xy term (spherical, or cylinder at 0 or 90) is loaded by psf_load_aperture.comp from
  // a per-column and a per-row factor; one with an xy term by psf_load_aperture_astigmatic.comp,
  // which adds the cross term. Throws std::invalid_argument for a wavelength that is not positive.
  void load_field(const ApertureGeometry& geometry, double wavelength_nm);
  // The same phase on the aperture last drawn (for timing the phase alone); the same refusal.
  void apply_phase(const DioptricPower& error, double wavelength_nm);
  // The FFT's buffer, N x N row-major, row 0 at the top: the pupil function after load_field().
  std::vector<std::complex<float>> read_field() const;

  // Y PSF at one wavelength (channels = 1).
  Psf monochromatic(const ApertureGeometry& geometry, double wavelength_nm);
  // Linear Rec.709 PSF (channels = 3) from the PSF at reference_wavelength_nm (the paper uses 575 nm).
  Psf spectral(const ApertureGeometry& geometry, int wavelength_count = 32, double reference_wavelength_nm = 575.0);

  // Linear Rec.709 PSF (channels = 3) with the eye's longitudinal chromatic aberration: the operator
  // of glare/wave/chromatic_psf.h (compute_chromatic_psf, its float64 reference) on the GPU. Selected by
  // calling it instead of spectral(), which keeps its scaled-reference result unchanged. For each of
  // Ritschel's wavelengths lambda_i = 380 + i (770 - 380) / n nm one FFT of the aperture (drawn once)
  // times the phase of E_i = geometry.total_power_error() + [LCA(lambda_i) - LCA(lambda_ref)] I
  // (glare/refraction/chromatic_eye.h, Thibos et al. 1992), its |F|^2 resampled onto the reference grid (pixels
  // of lambda_ref / W) with the Jacobian (lambda_ref / lambda_i)^2 and added with the CIE 1931 CMF
  // weights in linear Rec.709 (glare/wave/spectral_accumulation.h); negative values clamped, each channel
  // normalised to sum 1. Throws std::invalid_argument for wavelength_count < 1 and for a reference
  // wavelength that is not positive or that the LCA fit cannot take (<= 214.1 nm), before anything is
  // drawn; ClosedApertureError when no light passes.
  Psf chromatic(const ApertureGeometry& geometry, int wavelength_count = 32, double reference_wavelength_nm = 575.0);
  // The last chromatic PSF's phase sampling check, as compute_chromatic_psf reports it: the check
  // the CPU makes for each wavelength's error (glare/wave/fresnel.h's for a spherical one, the strongest
  // meridian's for an astigmatic one), the warning of the most aliased wavelength with " (at X nm)"
  // or empty, and how many wavelengths aliased.
  const std::string& chromatic_sampling_warning() const { return chromatic_warning_; }
  int chromatic_aliased_wavelengths() const { return chromatic_aliased_; }

  // The same work without reading back (for timing): the result stays in result_buffer(). A closed
  // aperture is found by read() (ClosedApertureError), not here: no GPU round trip before it.
  void run_monochromatic(const ApertureGeometry& geometry, double wavelength_nm);
  void run_spectral(const ApertureGeometry& geometry, int wavelength_count, double reference_wavelength_nm);
  void run_chromatic(const ApertureGeometry& geometry, int wavelength_count, double reference_wavelength_nm);
  GLuint result_buffer(int channels) const { return channels == 1 ? power_.get() : spectral_.get(); }
  // Throws ClosedApertureError when the aperture transmitted no light (a channel's sum not > 0).
  Psf read(int channels, double wavelength_nm) const;

  int size_px() const { return size_px_; }
  double degrees_per_pixel(double wavelength_nm) const;

 private:
  void normalise(GLuint values, int channels);
  // Every (power error, wavelength) a PSF needs, its per-column and per-row phase factors, into a
  // new buffer of slots (phases_); then the aperture times slot `slot`'s phase into the FFT's buffer.
  void upload_phases(const std::vector<std::pair<DioptricPower, double>>& phases);
  void load_with_phase(const DioptricPower& error, double wavelength_nm, std::size_t slot);

  int size_px_;
  GlAperture aperture_;
  GlFft fft_;
  Program load_program_, astigmatic_load_program_, power_program_, reduce_program_, normalise_program_, spectral_program_,
      chromatic_program_, clamp_program_;
  std::string chromatic_warning_;
  int chromatic_aliased_ = 0;
  std::size_t phase_slot_bytes_ = 0;  // one axis' factors, rounded up to the binding alignment
  Buffer phases_, cross_table_, power_, spectral_, weights_, partial_a_, partial_b_;
  // Each result's channel sums before its normalisation (copied on the GPU), read with it.
  Buffer power_sums_, spectral_sums_;
};

}  // namespace glarelab::gl
