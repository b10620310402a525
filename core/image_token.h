#pragma once
// Names an image for the caches that keep state for it: a session's seen image on the GPU
// (FrameFacts::gpu_scene_token), the glare stage's composed frame (its hybrid source), a layer's kept
// glare (StaticLayerGlare::Kept::serial) and a glared region drawn (GlaredRegion::serial). One counter
// for every kind, so that a cache handed tokens by two callers (the GL convolution's kept image
// spectrum: the seen image's and the hybrid eye's energy image) never takes one image for another.
#include <cstdint>

namespace glarelab {

// Unique in the process, from any thread; never 0, which names no image.
std::uint64_t new_image_token();

}  // namespace glarelab
