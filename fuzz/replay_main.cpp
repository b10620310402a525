// The normal build's driver for a fuzz target (no libFuzzer, any compiler): runs
// LLVMFuzzerTestOneInput over every file of the seed corpus, then over deterministic mutations of
// those seeds drawn from the project's counter-based generator (core/random.h), so that the test
// suite runs a short, reproducible fuzz of each target and a crash names the input that caused it.
//   <target>_replay [--mutations N] [--seconds S] [--save-dir DIR] PATH...
// PATH is a file or a folder (read recursively, in sorted order). Mutations stop at N or after S
// seconds, whichever is first. An input that aborts, crashes or throws out of the target ends the
// run like any crash; before each mutated input runs it is written to DIR/<program>.last-input, so
// it can be replayed alone (`<target>_replay DIR/<target>_replay.last-input`) or handed to the
// libFuzzer build. The file is removed when the run ends without a finding.
#include <algorithm>
#include <chrono>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "core/random.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size);

namespace {

namespace fs = std::filesystem;
using Bytes = std::vector<std::uint8_t>;

Bytes read_file(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  return Bytes(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

void write_file(const fs::path& path, const Bytes& bytes) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
}

void run_one(const Bytes& bytes) {
  // data() of an empty vector may be null; libFuzzer always passes a valid pointer.
  static const std::uint8_t empty = 0;
  LLVMFuzzerTestOneInput(bytes.empty() ? &empty : bytes.data(), bytes.size());
}

// Fragments that matter to the formats under test (TOML, CSV, scripts, msgpack), inserted whole so
// that a few thousand mutations reach past the first syntax check.
const std::vector<std::string>& dictionary() {
  static const std::vector<std::string> words = {
      "\n", "\r\n", "\"", "\"\"", ",", "=", "[", "]", "[[", "]]", "{", "}", "#", " ", "\t", ".", "-", "+",
      "0", "1", "-1", "255", "65536", "2147483647", "-2147483648", "4294967296", "9223372036854775807",
      "1e308", "-1e308", "1e-320", "nan", "inf", "-inf", "0.5", "true", "false", "abort", "timeout", "onset",
      "offset", "left", "right", "\xc0", "\xdc\xff\xff", "\xdd\xff\xff\xff\xff", "\xdf\xff\xff\xff\xff",
      "\xcb\x7f\xf8\x00\x00\x00\x00\x00\x00", "\xcb\x7f\xf0\x00\x00\x00\x00\x00\x00", "\xff\xff\xff\x7f",
      "\x00\x00\x00\x80", "\xff\xff\xff\xff"};
  return words;
}

// One to four edits of `input`, from counter `index` of the fuzz_mutation stream (sub-indices
// number the draws within one mutation).
Bytes mutate(Bytes input, const std::vector<Bytes>& seeds, const glarelab::CounterRandom& random, std::uint64_t index) {
  std::uint32_t draw = 0;
  auto below = [&](std::size_t bound) {
    return bound == 0 ? std::size_t{0} : static_cast<std::size_t>(random.below(bound, index, draw++));
  };
  const std::size_t edits = 1 + below(4);
  for (std::size_t e = 0; e < edits; ++e) {
    const std::size_t at = below(input.size() + 1);
    switch (below(8)) {
      case 0:  // flip a bit
        if (!input.empty()) input[std::min(at, input.size() - 1)] ^= static_cast<std::uint8_t>(1u << below(8));
        break;
      case 1:  // a random byte
        if (!input.empty()) input[std::min(at, input.size() - 1)] = static_cast<std::uint8_t>(below(256));
        break;
      case 2:  // insert a random byte
        input.insert(input.begin() + static_cast<std::ptrdiff_t>(at), static_cast<std::uint8_t>(below(256)));
        break;
      case 3: {  // delete a range
        const std::size_t length = std::min(input.size() - at, 1 + below(16));
        input.erase(input.begin() + static_cast<std::ptrdiff_t>(at), input.begin() + static_cast<std::ptrdiff_t>(at + length));
        break;
      }
      case 4: {  // duplicate a range
        const std::size_t length = std::min(input.size() - at, 1 + below(64));
        const Bytes copy(input.begin() + static_cast<std::ptrdiff_t>(at), input.begin() + static_cast<std::ptrdiff_t>(at + length));
        input.insert(input.begin() + static_cast<std::ptrdiff_t>(at), copy.begin(), copy.end());
        break;
      }
      case 5: {  // insert a dictionary word
        const std::string& word = dictionary()[below(dictionary().size())];
        input.insert(input.begin() + static_cast<std::ptrdiff_t>(at), word.begin(), word.end());
        break;
      }
      case 6:  // truncate
        input.resize(at);
        break;
      default: {  // splice in a piece of another seed
        const Bytes& other = seeds[below(seeds.size())];
        const std::size_t from = below(other.size() + 1);
        const std::size_t length = std::min(other.size() - from, 1 + below(128));
        input.insert(input.begin() + static_cast<std::ptrdiff_t>(at), other.begin() + static_cast<std::ptrdiff_t>(from),
                     other.begin() + static_cast<std::ptrdiff_t>(from + length));
        break;
      }
    }
  }
  return input;
}

}  // namespace

int main(int argc, char** argv) {
  std::uint64_t mutations = 0;
  double seconds = 5.0;
  fs::path save_dir = ".";
  std::vector<fs::path> files;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--mutations" && i + 1 < argc) {
      mutations = std::strtoull(argv[++i], nullptr, 10);
    } else if (arg == "--seconds" && i + 1 < argc) {
      seconds = std::strtod(argv[++i], nullptr);
    } else if (arg == "--save-dir" && i + 1 < argc) {
      save_dir = argv[++i];
    } else if (fs::is_directory(arg)) {
      std::vector<fs::path> found;
      for (const auto& entry : fs::recursive_directory_iterator(arg))
        if (entry.is_regular_file()) found.push_back(entry.path());
      std::sort(found.begin(), found.end());
      files.insert(files.end(), found.begin(), found.end());
    } else if (fs::is_regular_file(arg)) {
      files.push_back(arg);
    } else {
      std::fprintf(stderr, "%s: no such file or folder: %s\n", argv[0], arg.c_str());
      return 2;
    }
  }
  if (files.empty()) {
    std::fprintf(stderr, "usage: %s [--mutations N] [--seconds S] [--save-dir DIR] PATH...\n", argv[0]);
    return 2;
  }

  std::vector<Bytes> seeds;
  for (const fs::path& file : files) {
    std::printf("replay: %s\n", file.string().c_str());
    std::fflush(stdout);  // the last name printed is the input that crashed
    seeds.push_back(read_file(file));
    run_one(seeds.back());
  }

  const glarelab::CounterRandom random(20240601, glarelab::RandomStream::fuzz_mutation);
  const auto start = std::chrono::steady_clock::now();
  const fs::path last_input = save_dir / (fs::path(argv[0]).filename().string() + ".last-input");
  std::uint64_t done = 0;
  for (; done < mutations; ++done) {
    if (std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() > seconds) break;
    const Bytes input = mutate(seeds[static_cast<std::size_t>(random.below(seeds.size(), done, 100))], seeds, random, done);
    write_file(last_input, input);
    run_one(input);
  }
  std::error_code ignored;
  fs::remove(last_input, ignored);
  std::printf("replay: %zu seed inputs and %llu of %llu mutations ran without a finding (%.1f s)\n", seeds.size(),
              static_cast<unsigned long long>(done), static_cast<unsigned long long>(mutations),
              std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
  return 0;
}
