#pragma once
// `glarelab psf --model luidolt`: Luidolt 2020's glare kernel (glare/wave/luidolt_kernel.h) for one
// pupil, written as EXR (R, G, B on its own grid, lambda / W degrees per pixel) and as a profile.
#include "runner/cli/psf_options.h"

namespace glarelab::cli {

// The pupil is --pupil-diameter-mm, or the eye model's at --time-s with --mode static or dynamic
// (particles from --seed, as a session's from its seed); --grid is the grid asked for, enlarged as
// Eq. 5.6's sampling condition demands (printed); --wavelength-samples is k + 1 of Eq. 5.13;
// --aperture-width-mm the particle texture's side (default the thesis' 8 mm). Every other model's
// option is refused (ConfigError naming it).
int run_luidolt_psf(const PsfArguments& args, const PsfOptionHandles& handles);

}  // namespace glarelab::cli
