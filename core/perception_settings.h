#pragma once
// The plain parameters of the perception stages of Luidolt 2020 (stimuli/perception/, Fig. 6.1's
// order: adaptation -> glare -> acuity -> tone mapping -> scotopic colour), with their defaults.
// They live here, below both stimuli/ (which runs the stages) and protocols/ (whose [perception]
// table is read into them, protocols/perception_config.h), as glare/glare_spec.h does for glare.
// The equations each parameter belongs to are documented beside the stage that uses it.
#include <string>

namespace glarelab {

// Section 5.1, stimuli/perception/frame_adaptation_luminance.h.
struct AdaptationWeighting {
  // Standard deviation of the gaze Gaussian in units of the frame width.
  double gaze_sigma_frame_widths = 0.125;
  int resampled_size_px = 128;  // section 5.1: "downsample our scene to a size of 128 x 128"
  int top_level_size_px = 16;   // "a Gaussian pyramid until 16 x 16 pixels"
};

// Eqs. 5.2-5.4, stimuli/perception/temporal_adaptation.h.
struct AdaptationTimeConstants {
  double rod_time_constant_s = 0.4;            // tau_rod, Eq. 5.3
  double cone_time_constant_s = 0.1;           // tau_cone, Eq. 5.3
  double rod_half_sensitivity_cd_m2 = 0.04;    // Y_half of Eq. 5.4
};

// Section 5.3, stimuli/perception/acuity_loss.h.
enum class AcuitySigmaForm {
  resolvable_frequency,  // Eq. 5.15 with the display's pixels per degree, only where L* < 1
  luidolt_linear,        // Eq. 5.16, sigma = max(1 - L*, 0) pixels
};

enum class SecondPassSigma {
  filtered_lightness,  // section 5.3.1, step 3: sigma from the horizontally blurred lightness
  original_lightness,  // Fig. 5.9: sigma from the lightness before either pass
};

struct AcuitySettings {
  AcuitySigmaForm sigma_form = AcuitySigmaForm::resolvable_frequency;
  SecondPassSigma second_pass = SecondPassSigma::filtered_lightness;
  double reference_white_cd_m2 = 100.0;  // Y_n of L*a*b* (lab_colour.h)
  double max_sigma_px = 1.0;             // kernel bound: s = 2 floor(3 sigma) + 1 <= 7
};

// Section 6.1, stimuli/perception/tone_mapping.h.
enum class ToneCurve {
  aces_narkowicz,  // Narkowicz's luminance-only fit (the thesis' curve as published in closed form)
  aces_hill,       // Hill's fit with the RRT and ODT colour matrices
  none,            // linear, clipped at the display peak
};

struct ToneMappingSettings {
  ToneCurve curve = ToneCurve::aces_narkowicz;
  double middle_grey = 0.18;                           // the scene-linear value L_a maps to (ACES)
  double aces_pre_exposure = 0.6;                      // Narkowicz: input x 0.6 for the original ACES curve
                                                       // (aces_narkowicz only)
  double minimum_adapted_luminance_cd_m2 = 1e-6;       // floor of L_a
};

// Section 5.4, stimuli/perception/scotopic_colour.h.
enum class ScotopicForm {
  luidolt_tint,          // Eq. 5.18
  spencer_desaturation,  // Spencer 1995, HSV saturation reduced by 70 % under full rod vision
};

struct ScotopicSettings {
  ScotopicForm form = ScotopicForm::luidolt_tint;
  double spencer_saturation_reduction = 0.7;  // Spencer 1995 section 5, at full rod sensitivity
};

// The stages' switches and parameters (stimuli/perception/perception_stages.h runs them). Every
// stage is on here, as the thesis' full pipeline; an experiment file's [perception] table starts
// from every stage off (protocols/perception_config.h).
struct PerceptionSettings {
  bool adaptation = true;
  bool glare = true;
  bool acuity = true;
  bool tone_mapping = true;
  bool scotopic = true;
  AdaptationWeighting adaptation_weighting;
  AdaptationTimeConstants adaptation_time_constants;
  AcuitySettings acuity_settings;
  ToneMappingSettings tone_mapping_settings;  // .curve: aces_narkowicz, aces_hill or none
  ScotopicSettings scotopic_settings;         // .form: luidolt_tint or spencer_desaturation
};

// Experiment-file spellings; a wrong one throws std::invalid_argument naming the field and the
// accepted values. to_string gives the spelling back.
ToneCurve parse_tone_curve(const std::string& text);               // "aces_narkowicz", "aces_hill", "none"
ScotopicForm parse_scotopic_form(const std::string& text);         // "luidolt_tint", "spencer_desaturation"
AcuitySigmaForm parse_acuity_sigma_form(const std::string& text);  // "resolvable_frequency", "luidolt_linear"
SecondPassSigma parse_second_pass_sigma(const std::string& text);  // "filtered_lightness", "original_lightness"
std::string to_string(ToneCurve curve);
std::string to_string(ScotopicForm form);
std::string to_string(AcuitySigmaForm form);
std::string to_string(SecondPassSigma pass);

}  // namespace glarelab
