#pragma once
// The observer's refraction and the spectacles worn, as an experiment file states them
// ([observer.refraction], [spectacles.NAME], [observer] spectacles and the per-condition column
// "spectacles"; docs/EXPERIMENT_FILES.md). Plain data below glare/ (which models the eye and the
// lenses from it: glare/refraction/dioptric_power.h and the refraction and lens models) and protocols/ (which
// reads the file), as core/perception_settings.h is for the perception stages.
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "core/spelling.h"

namespace glarelab {

// How the eye accommodates over a scene with depth ([observer] accommodation; docs/DEPTH_OF_FIELD.md,
// "Accommodation"). fixation: once, on the depth at its view's centre (Kakimoto et al. 2007 Eq. 13
// for that point), every other depth blurred by its defocus from there. range: each scene point
// with its own Eq. 13 (Kakimoto's Table 1 runs the accommodation step per voxel), so every point
// within the accommodation range (far point to near point) is sharp and one outside it blurs by its
// defocus from the nearer end.
enum class AccommodationRule { fixation, range };
inline constexpr Spelling<AccommodationRule> kAccommodationRuleSpellings[] = {{AccommodationRule::fixation, "fixation"},
                                                                              {AccommodationRule::range, "range"}};
constexpr std::span<const Spelling<AccommodationRule>> spellings(AccommodationRule) { return kAccommodationRuleSpellings; }

// A sphero-cylinder as clinics write it: sphere, cylinder in minus-cylinder form (<= 0), and the
// cylinder axis in TABO degrees (counterclockwise from the horizontal as the examiner facing the
// patient sees it, 0 on the examiner's right; glare/refraction/dioptric_power.h maps it into the observer's
// frame). Dioptres.
struct SpheroCylinder {
  double sphere_dioptres = 0.0;
  double cylinder_dioptres = 0.0;  // <= 0 in minus-cylinder form
  double axis_deg = 0.0;           // TABO, [0, 180)
};

// The observer's eye: its refractive error written as the prescription that corrects it, measured
// at a vertex distance, and the accommodation it has left.
struct ObserverRefractionSettings {
  SpheroCylinder prescription;
  double vertex_distance_mm = 12.0;  // back vertex of the trial lens to the cornea
  // Amplitude of accommodation; a negative value means "from [observer] age_years" (the age
  // formula is the refraction model's).
  double accommodation_amplitude_dioptres = -1.0;
};

// A pair of spectacles (the same lens for the eye that is modelled).
struct SpectaclesSettings {
  std::string name;  // the [spectacles.NAME] table it came from
  SpheroCylinder prescription;
  double vertex_distance_mm = 12.0;
  double refractive_index = 1.498;  // n_d; CR-39, the usual plastic
  double abbe_number = 58.0;        // V_d; CR-39
  double near_add_dioptres = 0.0;   // > 0: progressive, the add reached in the near zone below
  double decentration_x_mm = 0.0;   // optical centre from the line of sight, to the observer's right
  double decentration_y_mm = 0.0;   // and up (gives prism by Prentice's rule)
};

struct ObserverOptics {
  bool refraction_stated = false;  // [observer.refraction] present: the eye is modelled with it
  ObserverRefractionSettings refraction;
  std::vector<SpectaclesSettings> spectacles;  // every [spectacles.NAME] table, in file order
  std::string spectacles_worn = "none";        // [observer] spectacles: the default of the column
  // [observer] depth_of_field: true blurs every frame seen through the simulated eye by the depth of
  // its scene (docs/DEPTH_OF_FIELD.md, "In a session"), false never; absent: wherever the optics are
  // modelled and a scene shown carries a Z channel. Where it was written ("file:line:column").
  std::optional<bool> depth_of_field;
  std::string depth_of_field_where;
  // [observer] accommodation (fixation by default).
  AccommodationRule accommodation = AccommodationRule::fixation;

  // The spectacles called `name`, or nullptr for "none" or a name not defined.
  const SpectaclesSettings* find_spectacles(const std::string& name) const {
    for (const SpectaclesSettings& pair : spectacles)
      if (pair.name == name) return &pair;
    return nullptr;
  }
};

}  // namespace glarelab
