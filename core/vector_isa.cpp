#include "core/vector_isa.h"

namespace glarelab {

bool vector_isa_available(VectorIsa isa) {
  if (isa == VectorIsa::sse2) return true;
#if defined(__x86_64__) && defined(__GNUC__)
  static const bool avx2_fma = __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
  static const bool avx512 = avx2_fma && __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512vl") &&
                             __builtin_cpu_supports("avx512dq");
  return isa == VectorIsa::avx512 ? avx512 : avx2_fma;
#else
  return false;
#endif
}

VectorIsa widest_vector_isa() {
  return vector_isa_available(VectorIsa::avx2_fma) ? VectorIsa::avx2_fma : VectorIsa::sse2;
}

VectorIsa widest_vector_isa_with_avx512() {
  return vector_isa_available(VectorIsa::avx512) ? VectorIsa::avx512 : widest_vector_isa();
}

}  // namespace glarelab
