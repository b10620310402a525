#include "runner/cli/command_psf_eye.h"

#include <algorithm>

#include "glare/analytic/display_psf_image.h"
#include "glare/analytic/lenticular_halo.h"
#include "glare/eye/eye_model.h"
#include "protocols/glare_eye_file.h"

namespace glarelab::cli {

EyeParameters psf_eye_parameters(const PsfArguments& args, const std::string& mode) {
  EyeParameters parameters;
  if (!args.eye_from.empty()) read_glare_eye_file(args.eye_from, parameters);
  parameters.mode = parse_glare_mode(mode);
  parameters.initial_field_luminance_cd_m2 = args.field_luminance_cd_m2;
  return parameters;
}

double psf_halo_energy(const std::vector<ApertureLine>& grating_lines, const ApertureGeometry& kept,
                       const EyeParameters& parameters) {
  const bool gratings_kept = std::any_of(kept.lines.begin(), kept.lines.end(), [](const ApertureLine& line) {
    return line.component == ApertureComponent::gratings;
  });
  if (!gratings_kept || !kept.glare_enabled) return 0.0;
  return lenticular_halo_energy(grating_lines, halo_gratings(parameters), kept.pupil_diameter_mm);
}

DisplayKernel with_lenticular_halo(const DisplayKernel& far, const EyeParameters& parameters, double halo_energy,
                                   double degrees_per_pixel) {
  DisplayKernel out = far;
  if (out.channels == 1) {
    out.channels = 3;
    out.values.resize(3 * far.values.size());
    std::copy(far.values.begin(), far.values.end(), out.values.begin() + static_cast<std::ptrdiff_t>(far.values.size()));
    std::copy(far.values.begin(), far.values.end(), out.values.begin() + 2 * static_cast<std::ptrdiff_t>(far.values.size()));
  }
  if (!(halo_energy > 0.0)) return out;
  const DisplayKernel ring =
      lenticular_halo_kernel(LenticularHalo(halo_gratings(parameters)), flat_display_geometry(degrees_per_pixel));
  const int half_x = std::min(ring.half_width_px, out.half_width_px), half_y = std::min(ring.half_height_px, out.half_height_px);
  for (int c = 0; c < 3; ++c) {
    for (int dy = -half_y; dy <= half_y; ++dy)
      for (int dx = -half_x; dx <= half_x; ++dx) out.at(c, dx, dy) += halo_energy * ring.at(c, dx, dy);
    out.at(c, 0, 0) -= halo_energy;
  }
  return out;
}

}  // namespace glarelab::cli
