#pragma once
// Applies a glare condition to a composed HDR stimulus frame (cd/m2, linear Rec.709) at a session
// time: control returns the frame unchanged; static uses the eye frozen at GlareSpec::static_time_s;
// dynamic the eye of glare/eye_model.h at the frame's time. The glare itself is Ritschel et al. 2009
// sections 4-5: aperture -> monochromatic PSF at 575 nm -> spectral PSF (chromatic blur) -> mapped
// onto the display's pixels (glare/psf_scale.h) -> FFT convolution (glare/convolution_cpu.h).
//
// "Model only what a scene needs": the convolution is skipped when the glare cannot be visible
// anywhere in the frame (bound below), and the report says when the fibre gratings are behind the
// pupil (the eye model then leaves them out of the aperture; they change nothing).
#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <string>

#include "glare/eye_model.h"
#include "glare/psf.h"
#include "protocols/experiment.h"
#include "stimuli/image.h"

namespace glarelab {

struct GlareFrameReport {
  GlareMode mode = GlareMode::control;
  bool convolved = false;          // false for control and for skipped frames
  std::string skip_reason;         // non-empty when a dynamic or static frame was not convolved
  double pupil_diameter_mm = 0.0;  // 0 for control
  bool gratings_in_pupil = false;
  // The lids closed the pupil completely (a blink): no light, no PSF. A dynamic eye then holds the
  // PSF of the last frame it saw open (a closed eye's PSF is undefined, and dropping the glare for
  // the ~0.1 s of closure would flash the frame); with no such frame the glare is skipped.
  bool eye_closed = false;
  // Upper bound of max_x |glare(x) - frame(x)| / max(frame(x), floor) (see visibility_bound()).
  double visibility_bound = 0.0;
  double wing_fraction = 0.0;      // PSF energy outside the central display pixel (largest channel)
};

// Fraction of a display-scale PSF's energy outside its central pixel, largest over channels.
double psf_wing_fraction(const Psf& display_psf);
// Bound on the relative change glare makes anywhere in a frame. With a unit-sum PSF P and zero
// outside the image, glare(x) - L(x) = sum_{d != 0} (L(x - d) - L(x)) P(d), and for L >= 0 each
// |L(x - d) - L(x)| <= L_peak, so |change(x)| <= L_peak * wing_fraction; relative to
// max(L(x), floor) >= max(L_min, floor) this gives L_peak * wing / max(L_min, floor).
double visibility_bound(double peak_cd_m2, double min_cd_m2, double wing_fraction, double floor_cd_m2);

class GlareStage {
 public:
  // `seed` seeds the eye model (the session seed).
  GlareStage(const GlareSpec& spec, const DisplaySpec& display, std::uint64_t seed);
  ~GlareStage();

  ImageRGBA apply(const ImageRGBA& frame_cd_m2, GlareMode mode, double time_s, GlareFrameReport* report = nullptr);

  // The spectral PSF at the display's pixel scale for a mode and time (not for control), with the
  // eye adapted to `field_luminance_cd_m2`; nothing when the lids close the pupil completely.
  std::optional<Psf> display_psf(GlareMode mode, double time_s, double field_luminance_cd_m2, EyeState* state = nullptr);

 private:
  EyeModel& eye_for(GlareMode mode, double field_luminance_cd_m2);

  GlareSpec spec_;
  DisplaySpec display_;
  std::uint64_t seed_;
  // Dynamic: one eye for the whole session, starting adapted to the first frame it sees, recording
  // every frame's mean luminance (its pupil follows the field luminance).
  std::unique_ptr<EyeModel> dynamic_eye_;
  double last_recorded_s_ = -1.0;
  // Static: one frozen eye per field luminance (adapted to it), so identical frames give identical
  // glare at every time.
  std::map<double, std::unique_ptr<EyeModel>> static_eyes_;
  std::map<double, std::optional<Psf>> static_psfs_;
  std::optional<Psf> last_open_dynamic_psf_;
};

}  // namespace glarelab
