#pragma once
namespace glarelab {
// "VERSION+GITREV[-dirty]", recorded in sessions.software_version.
const char* software_version();
}  // namespace glarelab
