#pragma once
// The frame engine a session asks for: `[display] engine` in the experiment file, `--engine` on
// run, render and bench (the flag wins). stimuli/frame_engine.h answers it from its one table of
// engines; the words are this table's, for reading and for the log alike (core/spelling.h).
#include <span>

#include "core/spelling.h"

namespace glarelab {

// "cpu": the CPU engine. "gpu": the OpenGL 4.5 engine (the GL glare backend and the GL perception
// stages). "auto": the GPU engine on a hardware GPU with OpenGL 4.5, else the CPU engine.
enum class FrameEngineRequest { automatic, cpu, gpu };
inline constexpr Spelling<FrameEngineRequest> kFrameEngineRequestSpellings[] = {
    {FrameEngineRequest::automatic, "auto"}, {FrameEngineRequest::cpu, "cpu"}, {FrameEngineRequest::gpu, "gpu"}};
constexpr std::span<const Spelling<FrameEngineRequest>> spellings(FrameEngineRequest) {
  return kFrameEngineRequestSpellings;
}

}  // namespace glarelab
