// The two paths of tests/test_paths.h, given to this file alone by tests/CMakeLists.txt.
#include "test_paths.h"

namespace glarelab::test {

const char* source_dir() { return GLARELAB_SOURCE_DIR_PATH; }

const char* glarelab_binary() { return GLARELAB_BINARY_PATH; }

}  // namespace glarelab::test
