#pragma once
// The x86-64 vector instruction sets a per-pixel loop may be written for, one binary for every
// machine: the build targets baseline x86-64 (SSE2), and a loop written for AVX2 with FMA is
// compiled for it alone (`__attribute__((target("avx2,fma")))`) and taken only where the CPU
// reports both. The loops that have both forms take a VectorIsa, so tests run each form on a
// machine that has both and hold both to the same contracts.
namespace glarelab {

enum class VectorIsa {
  sse2,      // every x86-64 CPU (and the scalar form elsewhere)
  avx2_fma,  // 256-bit vectors and fused multiply-add
};

// Whether this CPU runs `isa`'s form (sse2 always).
bool vector_isa_available(VectorIsa isa);
// The widest form this CPU runs: what sessions take.
VectorIsa widest_vector_isa();

}  // namespace glarelab
