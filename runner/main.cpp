#include <cstdio>

#include "runner/software_version.h"

int main() {
  std::printf("glarelab %s\n", glarelab::software_version());
  return 0;
}
