// Fuzz target: the OpenEXR loader (core/exr_io.h), fed through a file as scenes are. Expected
// outcome for bad input: ImageError "FILE: what is wrong". An image that loads must hold
// width x height RGBA values.
//
// Inputs that make OpenEXR or read_exr allocate far more than the file holds are skipped, for the
// fuzzer's speed; none of this is a limit of the product (docs/HARDENING.md). The target walks the
// header as OpenEXR 3.1 reads it (a type of fixed size is read at its size whatever size the file
// declares, so the walk follows the library, not the declared sizes) and skips an input when
// - a value is allocated before it is read and is longer than the rest of the file (an unknown
//   attribute, a string, a string of a string vector, a preview image): OpenEXR allocates and
//   clears up to 2 GB for a 300-byte file before finding it short (read_exr then refuses it,
//   ImageError "truncated or corrupt"), which under ASan took seconds an input;
// - the data window or a tile covers more than kFuzzMaxPixels (below): read_exr takes up to
//   kMaxExrPixels and allocates up to 1 GiB for them, and OpenEXR's InputFile allocates line
//   buffers in proportion to the window's width before read_exr can look at the header (150 MB and
//   3 s of CPU under ASan for a 153-byte file declaring 14.7 million by 9 pixels, which read_exr
//   then refuses). The limit itself and its refusal before glarelab allocates are the ordinary
//   tests' job (Exr.ADataWindowLargerThanAnyStimulusIsRefusedBeforeAllocating).
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <optional>
#include <string>
#include <string_view>
#include <utility>

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

// The value sizes of OpenEXR 3.1's attribute types that read a fixed number of bytes whatever the
// size the file declares (TypedAttribute<T>::readValueFrom reads a T): the next attribute starts
// after these bytes, not after the declared size.
std::optional<std::size_t> fixed_value_bytes(std::string_view type) {
  static constexpr std::pair<std::string_view, std::size_t> kFixed[] = {
      {"box2i", 16},  {"box2f", 16},  {"chromaticities", 32}, {"compression", 1}, {"deepImageState", 1},
      {"double", 8},  {"envmap", 1},  {"float", 4},           {"int", 4},         {"keycode", 28},
      {"lineOrder", 1}, {"m33f", 36}, {"m33d", 72},           {"m44f", 64},       {"m44d", 128},
      {"rational", 8}, {"tiledesc", 9}, {"timecode", 8},      {"v2i", 8},         {"v2f", 8},
      {"v2d", 16},    {"v3i", 12},    {"v3f", 12},            {"v3d", 24}};
  for (const auto& [name, bytes] : kFixed) {
    if (name == type) return bytes;
  }
  return std::nullopt;
}

// What OpenEXR does with one header: the verdict on the input, or where the header ends.
enum class HeaderWalk { read, skip, refused };

// Walks the header attributes (name NUL, type NUL, int32 size, value) as OpenEXR 3.1 reads them,
// from `at` to the empty name that ends a header: skip when OpenEXR would allocate more than the
// file holds before finding it short (a value, a preview image, a string of a string vector), or
// the data window or a tile is larger than kFuzzMaxPixels; refused when OpenEXR stops reading the
// header before allocating anything (so nothing is skipped).
HeaderWalk walk_header(const std::uint8_t* data, std::size_t size, std::size_t& at) {
  const auto left = [&](std::size_t from) { return from <= size ? size - from : 0; };
  while (at < size) {
    if (data[at] == 0) {  // the empty name: end of the header
      ++at;
      return HeaderWalk::read;
    }
    std::string_view field[2];  // name and type, NUL-terminated
    for (auto& text : field) {
      const std::size_t from = at;
      while (at < size && data[at] != 0) ++at;
      text = std::string_view(reinterpret_cast<const char*>(data) + from, at - from);
      ++at;
    }
    if (left(at) < 4) return HeaderWalk::refused;
    const auto declared = static_cast<std::int32_t>(little_endian_u32(data + at));
    at += 4;
    if (declared < 0) return HeaderWalk::refused;  // "Invalid size field"
    const std::string_view name = field[0], type = field[1];
    const std::size_t value_at = at;
    if (const auto bytes = fixed_value_bytes(type)) {
      if (left(value_at) < *bytes) return HeaderWalk::refused;  // read past the end
      if (name == "dataWindow" && type == "box2i" && window_above_fuzz_bound(data + value_at)) {
        return HeaderWalk::skip;
      }
      if (type == "tiledesc") {
        const std::uint64_t tile_pixels = std::uint64_t{little_endian_u32(data + value_at)} *
                                          std::uint64_t{little_endian_u32(data + value_at + 4)};
        if (tile_pixels > static_cast<std::uint64_t>(kFuzzMaxPixels)) return HeaderWalk::skip;
      }
      at = value_at + *bytes;
    } else if (type == "chlist") {  // channels (name NUL, 16 bytes) up to an empty name
      while (at < size && data[at] != 0) {
        while (at < size && data[at] != 0) ++at;
        at += 1 + 16;
      }
      ++at;
    } else if (type == "preview") {  // width, height, then width x height RGBA bytes, allocated first
      if (left(value_at) < 8) return HeaderWalk::refused;
      const std::uint64_t image_bytes = 4 * std::uint64_t{little_endian_u32(data + value_at)} *
                                        std::uint64_t{little_endian_u32(data + value_at + 4)};
      if (image_bytes > left(value_at + 8)) return HeaderWalk::skip;
      at = value_at + 8 + static_cast<std::size_t>(image_bytes);
    } else if (type == "stringvector") {  // strings (int32 length, bytes) until the declared size
      std::size_t read = 0;
      while (read < static_cast<std::size_t>(declared)) {
        if (left(at) < 4) return HeaderWalk::refused;
        const auto length = static_cast<std::int32_t>(little_endian_u32(data + at));
        at += 4;
        read += 4;
        if (length < 0) return HeaderWalk::refused;
        if (static_cast<std::size_t>(length) > left(at)) return HeaderWalk::skip;
        at += static_cast<std::size_t>(length);
        read += static_cast<std::size_t>(length);
      }
    } else {  // string, floatvector, idmanifest and unknown types: the declared size, allocated first
      if (static_cast<std::size_t>(declared) > left(value_at)) return HeaderWalk::skip;
      at = value_at + (type == "floatvector" ? static_cast<std::size_t>(declared) / 4 * 4
                                             : static_cast<std::size_t>(declared));
    }
  }
  return HeaderWalk::refused;  // the file ends inside the header
}

// True for an input the fuzzer does not read (above): walks every part's header (a multi-part
// file's headers end with an empty header).
bool skipped_input(const std::uint8_t* data, std::size_t size) {
  std::size_t at = 8;  // magic and version
  if (size < at) return false;
  const bool multi_part = (data[5] & 0x10) != 0;
  do {
    if (multi_part && at < size && data[at] == 0) return false;  // the empty header after the last
    const HeaderWalk walk = walk_header(data, size, at);
    if (walk != HeaderWalk::read) return walk == HeaderWalk::skip;
  } while (multi_part);
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
