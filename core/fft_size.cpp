#include "core/fft_size.h"

#include <algorithm>
#include <initializer_list>

namespace glarelab {
namespace {

// Smallest n' >= n with no prime factor outside `primes`.
int smallest_size_with_factors(int n, std::initializer_list<int> primes) {
  for (int candidate = std::max(n, 1);; ++candidate) {
    int rest = candidate;
    for (int prime : primes)
      while (rest % prime == 0) rest /= prime;
    if (rest == 1) return candidate;
  }
}

}  // namespace

int smooth_fft_size(int n) { return smallest_size_with_factors(n, {2, 3, 5}); }

int good_fft_size(int n) { return smallest_size_with_factors(n, {2, 3, 5, 7}); }

}  // namespace glarelab
