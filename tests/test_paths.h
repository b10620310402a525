#pragma once
// Where the tests find the source tree and the glarelab executable. Every test source includes
// this header (tests/CMakeLists.txt, -include) instead of receiving the two paths as -D
// definitions: a definition holding the checkout's absolute path made every test object's compile
// command differ between checkouts, so the compiler cache could never reuse one built in another
// folder, while this text is the same everywhere. Only test_paths.cpp holds the paths.
namespace glarelab::test {

// The repository's root, without a trailing slash.
const char* source_dir();
// The glarelab executable built beside the tests.
const char* glarelab_binary();

}  // namespace glarelab::test

#define GLARELAB_SOURCE_DIR (::glarelab::test::source_dir())
#define GLARELAB_BINARY (::glarelab::test::glarelab_binary())
