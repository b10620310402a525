#pragma once
// The x86-64 vector instruction sets a per-pixel loop may be written for, one binary for every
// machine: the build targets baseline x86-64 (SSE2), and a loop written for AVX2 with FMA is
// compiled for it alone (`__attribute__((target("avx2,fma")))`) and taken only where the CPU
// reports both (and an AVX-512 form, where a loop has one, likewise). The loops that have several
// forms take a VectorIsa, so tests run each form on a machine that has them and hold all to the
// same contracts.
namespace glarelab {

enum class VectorIsa {
  sse2,      // every x86-64 CPU (and the scalar form elsewhere)
  avx2_fma,  // 256-bit vectors and fused multiply-add
  avx512,    // 512-bit vectors (AVX-512 F, VL and DQ) beside AVX2 and FMA: only loops that name it
};

// Whether this CPU runs `isa`'s form (sse2 always).
bool vector_isa_available(VectorIsa isa);
// The widest of sse2 and avx2_fma this CPU runs: what sessions take for a loop with those forms.
VectorIsa widest_vector_isa();
// The widest of all three this CPU runs, for a loop that has an avx512 form too.
VectorIsa widest_vector_isa_with_avx512();

}  // namespace glarelab
