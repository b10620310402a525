// Fuzz target: the OpenEXR loader (core/exr_io.h), fed through a file as scenes are. Expected
// outcome for bad input: ImageError "FILE: what is wrong". An image that loads must hold
// width x height RGBA values.
//
// Two kinds of input are skipped, both for the fuzzer's speed, neither a limit of the product
// (docs/HARDENING.md):
// - a header attribute declared longer than the file: OpenEXR (3.1) allocates and clears the
//   declared size before it finds the file too short, up to 2 GB for a 300-byte file (read_exr
//   then refuses the file, ImageError "truncated or corrupt"); under ASan each such input took
//   seconds and the fuzzer ran 7 inputs/s. The allocation is OpenEXR's, not glarelab's.
// - a data window of more than kFuzzMaxPixels (below): read_exr takes up to kMaxExrPixels and
//   allocates up to 1 GiB for them, and OpenEXR's InputFile allocates line buffers in proportion
//   to the window's width before read_exr can look at the header (150 MB and 3 s of CPU under
//   ASan for a 153-byte file declaring 14.7 million by 9 pixels, which read_exr then refuses);
//   near the old bound (the fuzzer's 2 GB memory limit) the target ran 90 inputs/s. The limit
//   itself and its refusal before glarelab allocates are the ordinary tests' job
//   (Exr.ADataWindowLargerThanAnyStimulusIsRefusedBeforeAllocating).
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <string_view>

#include "core/exr_io.h"
#include "fuzz/fuzz_support.h"

namespace {

// The largest data window read here, in pixels: 2^18, 4 MiB as float RGBA (5 MiB with Z). No
// path of the reader depends on the image's size below kMaxExrPixels: scanline and tiled files,
// every compression (a chunk is at most 256 lines), mipmap and ripmap levels, luminance/chroma
// subsampling and offset data windows all occur in images of a few pixels, so the bound keeps
// every parser path reachable and each input under a few milliseconds.
constexpr std::int64_t kFuzzMaxPixels = std::int64_t{1} << 18;

std::uint32_t little_endian_u32(const std::uint8_t* bytes) {
  return static_cast<std::uint32_t>(bytes[0]) | static_cast<std::uint32_t>(bytes[1]) << 8 |
         static_cast<std::uint32_t>(bytes[2]) << 16 | static_cast<std::uint32_t>(bytes[3]) << 24;
}

std::int64_t little_endian_i32(const std::uint8_t* bytes) {
  return static_cast<std::int32_t>(little_endian_u32(bytes));
}

// True for a dataWindow value (box2i: xMin, yMin, xMax, yMax) of more than kFuzzMaxPixels pixels.
bool window_above_fuzz_bound(const std::uint8_t* box) {
  const std::int64_t width = little_endian_i32(box + 8) - little_endian_i32(box) + 1;
  const std::int64_t height = little_endian_i32(box + 12) - little_endian_i32(box + 4) + 1;
  if (width <= 0 || height <= 0) return false;  // an empty window: OpenEXR refuses the header
  // Each side is below 2^33, so the product is formed only when it cannot overflow.
  return width > kFuzzMaxPixels || height > kFuzzMaxPixels || width * height > kFuzzMaxPixels;
}

// Walks the header attributes (name NUL, type NUL, int32 size, value) of every part until the
// empty name that ends a header (two in a row end a multi-part file's headers): true when one
// declares more bytes than the file has left, or is a dataWindow the fuzzer does not read
// (above).
bool skipped_input(const std::uint8_t* data, std::size_t size) {
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
    std::size_t field_at[2] = {};
    std::size_t field_length[2] = {};
    for (int field = 0; field < 2; ++field) {  // name and type, NUL-terminated
      field_at[field] = at;
      while (at < size && data[at] != 0) ++at;
      field_length[field] = at - field_at[field];
      ++at;
    }
    const auto field_is = [&](int field, std::string_view text) {
      return field_length[field] == text.size() && std::memcmp(data + field_at[field], text.data(), text.size()) == 0;
    };
    if (at + 4 > size) return false;
    const std::uint32_t length = little_endian_u32(data + at);
    at += 4;
    if (length > size - at) return true;
    if (length == 16 && field_is(0, "dataWindow") && field_is(1, "box2i") &&
        window_above_fuzz_bound(data + at)) {
      return true;
    }
    at += length;
  }
  return false;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace glarelab;
  if (skipped_input(data, size)) return 0;
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
