#pragma once
// The observer's refraction in each condition of a session (docs/REFRACTION.md, "In a session"):
// [observer.refraction] (the eye, its accommodation amplitude from the table or from [observer]
// age_years by Hofstetter's formula) and the spectacles the condition wears (column "spectacles",
// else [observer] spectacles) give, through glare/refraction/eye_refraction.h (Kakimoto et al. 2007, section
// 4.4), the residual power error at the display: the observer looks at the display, so the eye
// accommodates on it (Eq. 13) and what accommodation cannot reach is left as defocus and
// astigmatism. The glare stage puts that residual into every wave-optics PSF of the condition.
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "glare/refraction/dioptric_power.h"
#include "glare/refraction/eye_refraction.h"
#include "core/display_spec.h"
#include "core/image.h"
#include "glare/refraction/spectacle_lens.h"
#include "glare/glare_spec.h"
#include "protocols/experiment.h"

namespace glarelab {

class SpectacleWarpGridCache;  // stimuli/spectacle_warp.h

struct ConditionRefraction {
  std::string condition;               // the condition's name
  std::string spectacles = "none";     // the [spectacles.NAME] worn, or "none"
  std::optional<ThinSpectacleLens> lens;   // the lens at its vertex distance (none: the naked eye)
  // The same lens as a real lens (index, Abbe number, decentration, progressive add; glare/
  // glare/refraction/spectacle_lens.h), through which the frame is warped (stimuli/spectacle_warp.h): magnification,
  // distortion, prism and transverse chromatic aberration. Shared: the lens is immutable.
  std::shared_ptr<const SpectacleLens> traced_lens;
  // The lens' traced warp grids, kept from frame to frame while the display's frame stays the same
  // (shared by the condition's copies, as the lens is).
  std::shared_ptr<SpectacleWarpGridCache> warp_grids;
  double accommodation_amplitude_dioptres = 0.0;
  EyeRefraction eye;                   // the eye itself, amplitude included (depth of field uses it)
  std::string amplitude_source;        // where the amplitude came from, for the record
  DioptricPower ocular_refraction;     // K: the eye's error at the cornea
  double viewing_distance_m = 0.0;     // the display, from the cornea
  FixationRefraction fixation;         // V, Delta P and the residual E at the display
  // [observer] accommodation: how the depth of field accommodates over the scene's depths
  // (runner/session/condition_depth_of_field.h).
  AccommodationRule accommodation = AccommodationRule::fixation;
};

// True when the experiment models the observer's optics: [observer.refraction] is present, some
// condition wears spectacles or [observer] depth_of_field = true (an emmetrope without the table). Then every condition's wave-optics PSF carries its residual (zero for
// an emmetrope whose accommodation reaches the display, but with the eye's LCA all the same); when
// false no PSF carries a refractive error or the eye's LCA: each comes from the eye model's aperture alone.
bool models_observer_optics(const Experiment& experiment);

// The refraction of one condition; nothing when the experiment does not model the observer's
// optics. Throws ConfigError at the row when the display is not beyond the spectacles.
std::optional<ConditionRefraction> condition_refraction(const Experiment& experiment, const ConditionRow& row);
// The same for an experiment known to model the observer's optics: a loop over the rows asks
// models_observer_optics once, not once per row (that scan reads every row: quadratic in the table).
ConditionRefraction modelled_condition_refraction(const Experiment& experiment, const ConditionRow& row);

// Every condition's (empty when the optics are not modelled), in condition order.
std::vector<ConditionRefraction> condition_refractions(const Experiment& experiment);

// The largest pupil the session's eye can have (mm): the eye model's clamp ([glare.eye]
// pupil_max_diameter_mm), which a measured (tracker) pupil is also clamped to. The sampling check is
// made for it, so no frame aliases.
double largest_session_pupil_diameter_mm(const GlareSpec& spec);

// The frame seen through the condition's spectacles (stimuli/spectacle_warp.h): the display as a
// flat scene at its viewing distance, the primary line of sight through its centre, each channel at
// its own wavelength. The composed frame itself without spectacles.
ImageRGBA frame_through_spectacles(const ConditionRefraction& refraction, const DisplaySpec& display,
                                   const ImageRGBA& composed_cd_m2, int threads);

// Refusals before anything is written (ConfigError, exit 2), for each condition that shows
// wave-optics glare (ritschel, or the hybrid's near field) when the optics are modelled: a residual
// whose pupil phase the [glare] grid_px cannot sample at the largest pupil, at any of the spectral
// PSF's wavelengths with the eye's LCA (check_power_error_sampling, glare/refraction/astigmatic_phase.h);
// a glare condition of the analytic models (spencer, cie), which have no pupil to carry it; and
// spectacles whose lens cannot be built (glare/refraction/spectacle_lens.h's refusals) or does not cover the
// display (a line of sight to a corner misses the lens).
void check_condition_refractions(const Experiment& experiment);

// One line for the record: the condition, spectacles, amplitude, accommodation, the residual as a
// minus-cylinder prescription (sphere / cylinder x TABO axis, dioptres) and its geometric blur.
std::string describe_condition_refraction(const ConditionRefraction& refraction);

}  // namespace glarelab
