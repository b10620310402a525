#pragma once
// How a session's glare is computed and shown: the plain parameters of the glare engine and its
// stage (stimuli/glare_stage.h), with their defaults. The experiment file's [glare] table is read
// into this struct by protocols/glare_config.h; nothing here knows about experiment files.
#include <span>

#include "core/spelling.h"
#include "glare/analytic/analytic_psf.h"
#include "glare/eye/eye_parameters.h"
#include "glare/glare_backend_kind.h"
#include "glare/analytic/spencer_psf.h"

namespace glarelab {

// The choices below in the experiment file's words, one table each (core/spelling.h): the file is
// read and the resolved experiment and the log are written through them.
enum class PupilSource { tracker, model };
inline constexpr Spelling<PupilSource> kPupilSourceSpellings[] = {{PupilSource::tracker, "tracker"},
                                                                  {PupilSource::model, "model"}};
constexpr std::span<const Spelling<PupilSource>> spellings(PupilSource) { return kPupilSourceSpellings; }

enum class BlinkSource { model, tracker };
inline constexpr Spelling<BlinkSource> kBlinkSourceSpellings[] = {{BlinkSource::model, "model"},
                                                                  {BlinkSource::tracker, "tracker"}};
constexpr std::span<const Spelling<BlinkSource>> spellings(BlinkSource) { return kBlinkSourceSpellings; }

enum class GlarePresentationRequest { automatic, live, prepared };
inline constexpr Spelling<GlarePresentationRequest> kGlarePresentationRequestSpellings[] = {
    {GlarePresentationRequest::automatic, "auto"},
    {GlarePresentationRequest::live, "live"},
    {GlarePresentationRequest::prepared, "prepared"}};
constexpr std::span<const Spelling<GlarePresentationRequest>> spellings(GlarePresentationRequest) {
  return kGlarePresentationRequestSpellings;
}

enum class GlareSource { all, excess };
inline constexpr Spelling<GlareSource> kGlareSourceSpellings[] = {{GlareSource::all, "all"},
                                                                  {GlareSource::excess, "excess"}};
constexpr std::span<const Spelling<GlareSource>> spellings(GlareSource) { return kGlareSourceSpellings; }

struct GlareSpec {
  // Mode of conditions without a "glare" column value. Control by default: an experiment that does
  // not mention glare shows its scenes unchanged.
  GlareMode mode = GlareMode::control;
  double static_time_s = 0.0;         // the instant a static eye is frozen at
  int grid_px = 256;                  // aperture and PSF grid N (even)
  double aperture_width_mm = 10.0;    // side of the aperture grid: PSF pixel = lambda / width
  int supersampling = 2;              // aperture coverage sub-samples per pixel side (>= 2)
  int wavelength_samples = 32;        // chromatic blur samples over 380-770 nm (Ritschel section 5)
  // Visibility threshold for skipping a frame's glare: the largest relative change glare could make
  // anywhere in the frame must reach this Weber fraction (Spencer 1995 section 2: veiling luminance
  // is seen as a contrast against the local background; ~1% is the foveal Weber fraction).
  double visibility_weber_fraction = 0.01;
  // Luminance below which a relative change is measured against this floor instead (relative
  // changes of a black pixel are meaningless); 0.01 cd/m2 is near the bottom of mesopic vision.
  double visibility_floor_cd_m2 = 0.01;
  bool skip_invisible = true;         // false: always convolve (for measuring the skip error)
  // Compute backend (glare/glare_backend.h): "auto" (gl on a hardware GPU, else the planned float32
  // CPU path), "cpu" (FFTW double) or "gl" (OpenGL 4.5 compute; needs grid_px a power of two from 16
  // to 4096).
  GlareBackendRequest backend = GlareBackendRequest::automatic;
  // Gaze-contingent glare (Luidolt 2020, 5.2.3): 0 convolves the whole frame; a power of two
  // convolves that square window around the gaze and blends it in with a Gaussian falloff.
  int gaze_window_px = 0;
  // Latency compensation of the gaze that places the window (runner/tracker/gaze_prediction.h):
  // false (default) takes the latest confident gaze as it is; true extrapolates the recent gaze
  // track to the trial's first flip.
  bool gaze_latency_compensation = false;
  // The dynamic eye's pupil: "tracker" takes the tracker's filtered pupil when a tracker runs (the
  // model's Eq. 1-2 pupil otherwise), "model" always the model's.
  PupilSource pupil_source = PupilSource::tracker;
  // The dynamic eye's blinks: "model" its own schedule (glare/eye/eyelids.h), "tracker" the blinks the
  // tracker detects (Luidolt 2020, 7.2: a detected blink may drive the eyelids instead).
  BlinkSource blink_source = BlinkSource::model;
  // How a session presents glare trials (runner/session/trial_glare.cpp): "auto" measures the
  // first glare trial (prepared before onset) and computes every later frame live, just before its
  // flip, when that fits the refresh period; "live" always; "prepared" never.
  GlarePresentationRequest presentation = GlarePresentationRequest::automatic;

  // Which glare model makes the glare of conditions without a "glare_model" column value
  // (glare/analytic/analytic_psf.h): "human" (the default: the wave-optics eye's dynamic structure near
  // the source at the light CIE 146:2002 gives the observer on every ring, the CIE far field over the
  // whole display: glare/analytic/hybrid_psf.h, calibrated_near_psf), "ritschel" (the wave-optics eye
  // alone, within its grid's reach), "spencer", "cie" or "hybrid" (the wave-optics eye near the
  // source scaled by one energy rule, the analytic far field beyond).
  GlareModel model = GlareModel::human;
  // Spencer's mixture: photopic, mesopic, scotopic, or adaptive (default: by the frame's adaptation
  // luminance, blended smoothly across the band edges at 0.01 and 3 cd/m2).
  SpencerRegime spencer_regime = SpencerRegime::adaptive;
  // Spencer's flare lines (section 3.2; glare/analytic/spencer_flare_lines.h): random radial lines
  // multiplied into the corona (f1, f2) and the halo (f3), drawn from the session's seed. Off by
  // default, so a file that does not ask for them keeps its smooth P; rows of the hybrid keep a
  // smooth far field (their near field is the wave-optics eye's own corona).
  bool spencer_flare_lines = false;
  // The analytic far field of the hybrid eye: spencer or cie.
  GlareModel hybrid_far_field = GlareModel::spencer;
  // The hybrid's hand-over annulus in degrees from the source; 0: the default for the wave PSF's
  // reach (glare/analytic/hybrid_psf.h, default_handover). The outer radius must lie within the reach.
  double hybrid_handover_inner_deg = 0.0;
  double hybrid_handover_outer_deg = 0.0;
  // What light the glare spreads (Spencer 1995, section 3.2 end): "all" of the frame, or only the
  // "excess" above the display's peak (the viewer's own eye already scatters what the display
  // shows), added to the frame clipped at the peak.
  GlareSource source = GlareSource::all;
  // The observer's eye for the analytic models (Spencer Eq. 10, CIE 146): `[observer]` age_years
  // and pigmentation in the experiment file.
  ObserverEye observer_eye;
  // The eye model's parameters ([glare.eye], protocols/eye_parameters_config.h): every dynamic and
  // static eye of the session is built from them (mode, static instant and first field luminance
  // set per eye by the glare stage).
  EyeParameters eye;
};

}  // namespace glarelab
