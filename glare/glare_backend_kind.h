#pragma once
// The glare compute backends by kind, and what a user asks for ([glare] backend, `psf --backend`):
// the words of both, one table each (core/spelling.h). glare/glare_backend.h chooses among the kinds.
#include <span>

#include "core/spelling.h"

namespace glarelab {

// What is asked for: "auto" (gl on a hardware GPU, else the CPU), "cpu" or "gl".
enum class GlareBackendRequest { automatic, cpu, gl };
inline constexpr Spelling<GlareBackendRequest> kGlareBackendRequestSpellings[] = {
    {GlareBackendRequest::automatic, "auto"}, {GlareBackendRequest::cpu, "cpu"}, {GlareBackendRequest::gl, "gl"}};
constexpr std::span<const Spelling<GlareBackendRequest>> spellings(GlareBackendRequest) {
  return kGlareBackendRequestSpellings;
}

// What computes: the FFTW paths in double (the reference) and float (glare/cpu/backend.h), the
// planned float32 path of a session's frames (glare/cpu/float_glare.h) and OpenGL 4.5 compute
// (glare/gl/backend.h). The words are those the log, `psf` and `bench` print.
enum class GlareBackendKind { cpu_float64, cpu_float32, cpu_float32_planned, gl };
inline constexpr Spelling<GlareBackendKind> kGlareBackendKindSpellings[] = {
    {GlareBackendKind::cpu_float64, "cpu float64"},
    {GlareBackendKind::cpu_float32, "cpu float32"},
    {GlareBackendKind::cpu_float32_planned, "cpu float32 planned"},
    {GlareBackendKind::gl, "gl"}};
constexpr std::span<const Spelling<GlareBackendKind>> spellings(GlareBackendKind) { return kGlareBackendKindSpellings; }

}  // namespace glarelab
