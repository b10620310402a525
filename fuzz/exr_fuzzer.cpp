// Fuzz target: the OpenEXR loader (core/exr_io.h), fed through a file as scenes are. Expected
// outcome for bad input: ImageError "FILE: what is wrong". An image that loads must hold
// width x height RGBA values.
//
// Inputs whose header declares an attribute longer than the file are skipped: OpenEXR (3.1)
// allocates and clears the declared size before it finds the file too short, up to 2 GB for a
// 300-byte file. read_exr then refuses the file as it should (ImageError "truncated or corrupt"),
// but under ASan each such input takes seconds and the fuzzer spent nearly all its time on them
// (7 inputs/s). The allocation is OpenEXR's, not glarelab's; docs/HARDENING.md.
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "core/exr_io.h"
#include "fuzz/fuzz_support.h"

namespace {

// Walks the header attributes (name NUL, type NUL, int32 size, value) of every part until the
// empty name that ends a header (two in a row end a multi-part file's headers): true when one
// declares more bytes than the file has left.
bool declares_oversized_attribute(const std::uint8_t* data, std::size_t size) {
  std::size_t at = 8;  // magic and version
  if (size < at) return false;
  const bool multi_part = (data[5] & 0x10) != 0;
  bool previous_empty = false;
  while (at < size) {
    if (data[at] == 0) {  // end of one header
      ++at;
      if (!multi_part || previous_empty) return false;
      previous_empty = true;
      continue;
    }
    previous_empty = false;
    for (int field = 0; field < 2; ++field) {  // name and type, NUL-terminated
      while (at < size && data[at] != 0) ++at;
      ++at;
    }
    if (at + 4 > size) return false;
    const std::uint32_t length = static_cast<std::uint32_t>(data[at]) | static_cast<std::uint32_t>(data[at + 1]) << 8 |
                                 static_cast<std::uint32_t>(data[at + 2]) << 16 |
                                 static_cast<std::uint32_t>(data[at + 3]) << 24;
    at += 4;
    if (length > size - at) return true;
    at += length;
  }
  return false;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace glarelab;
  if (declares_oversized_attribute(data, size)) return 0;
  const std::string path =
      fuzz::ScratchFolder::instance().write("scene.exr", std::string_view(reinterpret_cast<const char*>(data), size));
  try {
    const ExrReadResult result = read_exr(path);
    const std::size_t expected =
        4 * static_cast<std::size_t>(result.image.width_px) * static_cast<std::size_t>(result.image.height_px);
    if (result.image.rgba.size() != expected) {
      std::fprintf(stderr, "%zu values for a %d x %d image\n", result.image.rgba.size(), result.image.width_px,
                   result.image.height_px);
      std::abort();
    }
  } catch (const ImageError&) {
  }
  return 0;
}
