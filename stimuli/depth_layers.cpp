#include "stimuli/depth_layers.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>

#include "glare/parallel_rows.h"
#include "stimuli/scene_depth.h"

namespace glarelab {
namespace {

// 1 / vergence, with vergence 0 at infinity.
double distance_for_vergence_m(double vergence) { return vergence == 0.0 ? INFINITY : 1.0 / vergence; }

DioptricPower checked_error(const EyeErrorAtDistance& error, double distance_m) {
  const DioptricPower power = error(distance_m);
  if (!std::isfinite(power.xx()) || !std::isfinite(power.xy()) || !std::isfinite(power.yy()) ||
      !std::isfinite(power.matrix_dioptres[0][1]))
    throw std::invalid_argument("stimuli/depth_layers: the eye's power error for a point at " +
                                std::to_string(distance_m) + " m is not finite");
  return power;
}

}  // namespace

double BlurGeometry::pixels_per_dioptre() const {
  return pupil_radius_m / (degrees_per_pixel * std::numbers::pi / 180.0);
}

double blur_error_px(const DioptricPower& first, const DioptricPower& second, const BlurGeometry& geometry) {
  const PrincipalPowers difference = principal_powers(first - second);
  return std::max(std::abs(difference.p1_dioptres), std::abs(difference.p2_dioptres)) * geometry.pixels_per_dioptre();
}

DepthLayerPlan plan_depth_layers(const std::vector<float>& depth_m, const BlurGeometry& geometry,
                                 const EyeErrorAtDistance& error, double tolerance_px, int threads) {
  if (!(geometry.degrees_per_pixel > 0.0) || !std::isfinite(geometry.degrees_per_pixel) ||
      !(geometry.pupil_radius_m > 0.0) || !std::isfinite(geometry.pupil_radius_m))
    throw std::invalid_argument("stimuli/depth_layers: degrees per pixel (" + std::to_string(geometry.degrees_per_pixel) +
                                ") and pupil radius (" + std::to_string(geometry.pupil_radius_m) +
                                " m) must be positive and finite");
  if (!(tolerance_px > 0.0) || !std::isfinite(tolerance_px))
    throw std::invalid_argument("stimuli/depth_layers: the layer tolerance " + std::to_string(tolerance_px) +
                                " px must be positive and finite");
  if (!error) throw std::invalid_argument("stimuli/depth_layers: no eye error function was given");

  // The distinct vergences of the scene, ascending (far to near). Runs of equal depth (a plane, a
  // row of a floor) are collapsed before sorting.
  std::vector<double> vergences;
  for (std::size_t k = 0; k < depth_m.size(); ++k)
    if (k == 0 || depth_m[k] != depth_m[k - 1]) vergences.push_back(vergence_dioptres(depth_m[k]));
  std::sort(vergences.begin(), vergences.end());
  vergences.erase(std::unique(vergences.begin(), vergences.end()), vergences.end());

  std::vector<DioptricPower> errors;
  errors.reserve(vergences.size());
  for (double v : vergences) errors.push_back(checked_error(error, distance_for_vergence_m(v)));

  DepthLayerPlan plan;
  for (std::size_t first = 0; first < vergences.size();) {
    std::size_t end = first + 1;
    while (end < vergences.size() && blur_error_px(errors[end], errors[first], geometry) <= 2.0 * tolerance_px) ++end;
    DepthLayer layer;
    layer.far_vergence_dioptres = vergences[first];
    layer.near_vergence_dioptres = vergences[end - 1];
    layer.vergence_dioptres = 0.5 * (layer.far_vergence_dioptres + layer.near_vergence_dioptres);
    const DioptricPower middle = checked_error(error, distance_for_vergence_m(layer.vergence_dioptres));
    layer.ellipse = pixel_blur_ellipse(middle, geometry.pupil_radius_m, geometry.degrees_per_pixel);
    for (std::size_t k = first; k < end; ++k)
      layer.max_blur_error_px = std::max(layer.max_blur_error_px, blur_error_px(errors[k], middle, geometry));
    layer.blurred = layer.ellipse.semi_major_px > tolerance_px;
    plan.layers.push_back(layer);
    first = end;
  }

  // Each pixel to the layer whose vergence range holds it.
  std::vector<double> near_bounds;
  for (const DepthLayer& layer : plan.layers) near_bounds.push_back(layer.near_vergence_dioptres);
  plan.layer_of_pixel.assign(depth_m.size(), 0);
  parallel_chunks(static_cast<int>(depth_m.size()), threads, [&](int begin, int stop) {
    for (int k = begin; k < stop; ++k) {
      const double v = vergence_dioptres(depth_m[static_cast<std::size_t>(k)]);
      plan.layer_of_pixel[static_cast<std::size_t>(k)] = static_cast<std::uint32_t>(
          std::lower_bound(near_bounds.begin(), near_bounds.end(), v) - near_bounds.begin());
    }
  });
  for (std::uint32_t index : plan.layer_of_pixel) ++plan.layers[index].pixel_count;
  return plan;
}

}  // namespace glarelab
