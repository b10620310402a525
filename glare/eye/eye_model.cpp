#include "glare/eye/eye_model.h"

#include <algorithm>
#include <cmath>
#include <iterator>
#include <stdexcept>
#include <string>

namespace glarelab {

namespace {
const EyeParameters& validated(const EyeParameters& parameters) {
  validate(parameters);
  return parameters;
}
}  // namespace

EyeModel::EyeModel(const EyeParameters& parameters, std::uint64_t seed)
    : parameters_(validated(parameters)),
      seed_(seed),
      field_(parameters),
      pupil_(parameters, seed),
      accommodation_(parameters, seed),
      lens_(parameters, seed),
      vitreous_(parameters, seed),
      cornea_retina_(parameters, seed),
      eyelids_(parameters, seed) {}

void EyeModel::record_frame_luminance(double time_s, double mean_luminance_cd_m2) {
  field_.record_frame(time_s, mean_luminance_cd_m2);
}

void EyeModel::record_measured_pupil(double time_s, double diameter_mm) {
  if (!std::isfinite(time_s) || !std::isfinite(diameter_mm) || !(diameter_mm > 0.0))
    throw std::invalid_argument("eye model: a measured pupil needs a finite time and a positive diameter");
  if (!measured_pupils_.empty() && time_s < measured_pupils_.back().first)
    throw std::invalid_argument("eye model: measured pupils must come in time order");
  measured_pupils_.emplace_back(time_s, diameter_mm);
}

double EyeModel::model_time_s(double time_s) const {
  if (!std::isfinite(time_s) || time_s < 0.0 || time_s > kMaxEyeModelTime_s)
    throw std::invalid_argument(std::string("eye model: time must be finite, >= 0 s and at most ") +
                                kMaxEyeModelTimeText + " (got " + std::to_string(time_s) + " s)");
  return parameters_.mode == GlareMode::static_eye ? parameters_.static_time_s : time_s;
}

EyeState EyeModel::state_at(double time_s) const {
  const double t = model_time_s(time_s);
  EyeState state;
  state.time_s = t;
  state.field_luminance_cd_m2 = field_.field_luminance_cd_m2(t);
  state.mean_pupil_diameter_mm = pupil_.mean_diameter_mm(state.field_luminance_cd_m2);
  state.pupil_diameter_mm = pupil_.hippus_diameter_mm(t, state.mean_pupil_diameter_mm);
  if (parameters_.mode == GlareMode::dynamic && !measured_pupils_.empty() && measured_pupils_.front().first <= t) {
    const auto after = std::upper_bound(measured_pupils_.begin(), measured_pupils_.end(), t,
                                        [](double time, const std::pair<double, double>& m) { return time < m.first; });
    state.pupil_diameter_mm = std::clamp(std::prev(after)->second, parameters_.pupil_min_diameter_mm,
                                         parameters_.pupil_max_diameter_mm);
  }
  // Ritschel 3.3: the low-frequency power follows the pupil size "as determined in Eq. 2".
  state.defocus_dioptres = accommodation_.fluctuation_dioptres(t, state.mean_pupil_diameter_mm);
  state.accommodation_dioptres = parameters_.accommodative_demand_dioptres + state.defocus_dioptres;
  state.lens_equator_displacement_mm = lens_.equator_displacement_mm(state.defocus_dioptres);
  const VitreousState vitreous = vitreous_.dynamics().state_at(t);
  state.vitreous_angle_rad = vitreous.angle_rad;
  state.vitreous_angular_velocity_rad_s = vitreous.angular_velocity_rad_s;
  state.blink_closure = eyelids_.blink_closure(t);
  state.lid_closure = eyelids_.lid_closure(t);
  state.gratings_in_pupil = lens_.gratings_visible(state.pupil_diameter_mm);
  return state;
}

ApertureGeometry EyeModel::geometry_at(double time_s) const {
  const EyeState state = state_at(time_s);
  ApertureGeometry geometry;
  geometry.pupil_diameter_mm = state.pupil_diameter_mm;
  if (parameters_.mode == GlareMode::control) {
    geometry.glare_enabled = false;
    return geometry;
  }
  geometry.defocus_dioptres = state.defocus_dioptres;
  // Front to back, as Ritschel section 5 draws them.
  geometry.discs.reserve(cornea_retina_.cornea().size() + lens_.particles().size() +
                         vitreous_.particles().size() + cornea_retina_.retina().size());
  // Each part tagged with its component as it is appended (ApertureComponent).
  const auto tag_new_discs = [&](std::size_t from, ApertureComponent component) {
    for (std::size_t k = from; k < geometry.discs.size(); ++k) geometry.discs[k].component = component;
  };
  std::size_t from = geometry.discs.size();
  geometry.discs.insert(geometry.discs.end(), cornea_retina_.cornea().begin(), cornea_retina_.cornea().end());
  tag_new_discs(from, ApertureComponent::cornea);
  from = geometry.discs.size();
  lens_.append_particles(state.lens_equator_displacement_mm, geometry.discs);
  tag_new_discs(from, ApertureComponent::lens);
  if (state.gratings_in_pupil)
    geometry.lines.insert(geometry.lines.end(), lens_.grating_lines().begin(), lens_.grating_lines().end());
  from = geometry.discs.size();
  vitreous_.append_particles(state.vitreous_angle_rad, geometry.discs);
  tag_new_discs(from, ApertureComponent::vitreous);
  from = geometry.discs.size();
  geometry.discs.insert(geometry.discs.end(), cornea_retina_.retina().begin(), cornea_retina_.retina().end());
  tag_new_discs(from, ApertureComponent::retina);
  eyelids_.append_occluders(state.lid_closure, geometry);
  return geometry;
}

}  // namespace glarelab
