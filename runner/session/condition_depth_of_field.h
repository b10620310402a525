#pragma once
// Depth of field in a session (docs/DEPTH_OF_FIELD.md, "In a session"): a frame whose scenes carry a
// Z channel (metres from the eye) is blurred, pixel by pixel, by the geometric blur of its own depth
// through the condition's eye (runner/session/condition_refraction.h: refraction, accommodation
// amplitude, spectacles), Kakimoto et al. 2007's blur field (Eqs. 8-9).
//
// Order: spectacle warp -> depth of field -> glare (and the perception stages). Kakimoto et al.
// trace each voxel's wavefront through the spectacle lens first and only then through the eye to
// the retina (section 4.3, Table 1), and the blur field is defined over scene points (section
// 4.4.2: each vertex displaced by the blur of its own voxel). So the blur acts on the frame as it
// reaches the eye through the lens (its pixels are the eye's lines of sight, the warp's output),
// and before the glare: the glare's PSF is one convolution over the retinal image, where a pixel no
// longer has one depth, while the depth of field is a property of each scene point. With the depth
// of field on, the glare's PSF carries no residual defocus (only the eye's LCA): the defocus of each
// depth is the depth-of-field blur, and the PSF of a defocused eye is, to its second moments
// exactly, the geometric blur convolved with the focused PSF (docs/REFRACTION.md, "Measured").
//
// The eye ([observer] accommodation = "fixation", the default): the observer looks at the display
// centre, so the eye accommodates (Eq. 13, clamped to [0, amplitude]) on the depth seen at the
// centre pixel (width / 2, height / 2) of `display` (in stereo each eye's view, a display of its
// own: runner/session/session_eyes.h) through the lens' power on that line of sight; every other
// point keeps that accommodation. With "range" each point gets its own Eq. 13 accommodation, as
// Kakimoto's Table 1 computes it per voxel: every point whose mean vergence at the cornea lies in the
// accommodation range [mean(K) - amplitude, mean(K)] (near point to far point) has no mean error (a
// sharp point for an eye without astigmatism), and one outside keeps the error of the nearer end,
// plus the vergence beyond it. Through spectacles each
// pixel's line of sight has its own lens power (glare/refraction/spectacle_power.h, lens_power_at_gaze at the
// vertex sphere: oblique astigmatism, a progressive lens' near zone below the fitting cross), added
// to the point's vergence at the lens and carried to the cornea (Eq. 1); the blur uses it per display
// region (stimuli/directional_depth_of_field.h). Pupil: Ritschel et al. 2009 Eq. 2 (Moon and
// Spencer) for the frame's mean luminance, the static eye's mean pupil.
#include <string>
#include <vector>

#include "core/display_spec.h"
#include "core/image.h"
#include "glare/refraction/dioptric_power.h"
#include "protocols/experiment.h"
#include "runner/session/condition_refraction.h"
#include "stimuli/depth_layers.h"
#include "stimuli/directional_depth_of_field.h"
#include "stimuli/scene_library.h"

namespace glarelab {

// Whether a frame showing these scenes is blurred by depth: [observer] depth_of_field when given;
// absent, when the observer's optics are modelled (models_observer_optics) and a scene carries Z.
bool depth_of_field_applies(const Experiment& experiment, const std::vector<const LoadedScene*>& shown);

// Refusals before anything is written (ConfigError, exit 2): depth_of_field = true with a scene
// that has no Z channel (named, with its file); a scene with Z whose nearest depth does not lie
// beyond a condition's spectacles (the lens' front vertex), when the depth of field can apply.
void check_depth_of_field(const Experiment& experiment, const SceneLibrary& scenes);

// The eye's error along each line of sight of the frame, accommodated on `fixation_distance_m`
// seen along the centre pixel's line of sight, or on each depth within the range, as
// refraction.accommodation says (see above).
struct FrameEye {
  double fixation_distance_m = 0.0;
  DioptricPower fixation_vergence;      // at the cornea
  double accommodation_dioptres = 0.0;  // Eq. 13 at the fixation
  DioptricPower residual_at_fixation;   // E there
  EyeErrorAlongSightLine error;         // E for each line of sight and distance
  AccommodationRule rule = AccommodationRule::fixation;
  // The accommodation range as mean vergences at the cornea: mean(K) (far point) and
  // mean(K) - amplitude (near point).
  double range_far_vergence_dioptres = 0.0;
  double range_near_vergence_dioptres = 0.0;
};
FrameEye frame_eye(const ConditionRefraction& refraction, const DisplaySpec& display, double fixation_distance_m);

// The composed frame's depth (stimuli/frame_depth.h) as the eye sees it: through the condition's
// spectacles, warped with the frame; as it is without.
std::vector<float> seen_depth_m(const ConditionRefraction& refraction, const DisplaySpec& display,
                                const std::vector<float>& composed_depth_m, int threads);

struct FrameDepthOfField {
  ImageRGBA image_cd_m2;
  FrameEye eye;
  double pupil_diameter_mm = 0.0;
  DirectionalDepthOfFieldReport report;
};

// `seen_cd_m2` and `depth_m`: the frame and its depth as they reach the eye (after the spectacle
// warp); `field_cd_m2`: the luminance the pupil adapts to (Eq. 2).
FrameDepthOfField depth_of_field_frame(const ConditionRefraction& refraction, const DisplaySpec& display,
                                       const ImageRGBA& seen_cd_m2, const std::vector<float>& depth_m,
                                       double field_cd_m2, int threads);

// For the trial's glare label: fixation distance, accommodation, residual there, pupil, layers and
// regions.
std::string describe_frame_depth_of_field(const FrameDepthOfField& frame);

}  // namespace glarelab
