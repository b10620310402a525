#pragma once
// The folder where glarelab keeps, for later processes, what one process measured or integrated at
// a cost (FFTW's wisdom, glare/cpu/fftw_wisdom.h; the analytic kernels, glare/analytic/kernel_cache.h):
// $XDG_CACHE_HOME/glarelab where that is an absolute path, else $HOME/.cache/glarelab (the XDG base
// directory rule). Each user's own environment variable beside it overrides this.
#include <filesystem>
#include <optional>

namespace glarelab {

// The folder (not created), or nothing when neither variable holds an absolute path.
std::optional<std::filesystem::path> user_cache_folder();

}  // namespace glarelab
