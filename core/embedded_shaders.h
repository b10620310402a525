#pragma once
// Shader sources embedded at build time (cmake/EmbedShaders.cmake), keyed by their path relative to
// the source root, e.g. "stimuli/shaders/placed_image.frag". Every one was validated by glslangValidator.
#include <string_view>
#include <vector>

namespace glarelab {
// Empty view when no shader has that path.
std::string_view embedded_shader(std::string_view path);
std::vector<std::string_view> embedded_shader_names();
}  // namespace glarelab
