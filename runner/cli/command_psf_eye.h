#pragma once
// The eye model of `glarelab psf` (runner/cli/command_psf.cpp): its parameters (the defaults, the
// mode, the field luminance and, with --eye-from, an experiment file's [glare.eye]) and, for the
// human eye, the lenticular halo a session adds to the kernel when the pupil uncovers the lens-fibre
// gratings (glare/analytic/lenticular_halo.h, docs/GLARE_OPTICS.md 9.8), so that psf writes the
// kernel a session's frames take.
#include <string>
#include <vector>

#include "glare/analytic/lenticular_halo.h"
#include "glare/eye/aperture_geometry.h"
#include "glare/eye/eye_parameters.h"
#include "runner/cli/psf_options.h"

namespace glarelab::cli {

// The eye model's parameters for --mode `mode` at --field-luminance-cd-m2, over --eye-from's
// [glare.eye] when given.
EyeParameters psf_eye_parameters(const PsfArguments& args, const std::string& mode);

// The share of the light the gratings send into the halo (lenticular_halo_energy): the eye model's
// grating lines when `kept` (the geometry after --components) holds any, through its pupil; else 0.
double psf_halo_energy(const std::vector<ApertureLine>& grating_lines, const ApertureGeometry& kept,
                       const EyeParameters& parameters);

// far + halo_energy (K_halo - delta), as the session's glare stage composes the human eye's kernel:
// the ring on the display's pixels (lenticular_halo_kernel on flat_display_geometry) within far's
// half sizes, its light taken from the source's pixel. far becomes 3 channels.
DisplayKernel with_lenticular_halo(const DisplayKernel& far, const EyeParameters& parameters, double halo_energy,
                                   double degrees_per_pixel);

}  // namespace glarelab::cli
