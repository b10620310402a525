#pragma once
// One way to turn an OpenXR call's failure into the display's error, for the OpenXR backend's files
// (runner/display/openxr_*.cpp). Only built where CMake found the loader.
#include <openxr/openxr.h>

#include <string>

namespace glarelab {

// The result's name from the runtime (xrResultToString), else from the loader's own failures,
// else its number: with no instance yet (the loader found no runtime) only the last two exist.
std::string openxr_result_text(XrInstance instance, XrResult result);

// Throws DisplayError "OpenXR: WHAT failed (RESULT)" when the call failed.
void check_openxr(XrResult result, XrInstance instance, const std::string& what);

}  // namespace glarelab
