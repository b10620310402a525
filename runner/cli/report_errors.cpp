// The one place error types become exit codes (README "Exit codes"): 2 for input that cannot be
// used, 3 for a display, GL or device that cannot deliver, 4 for storage; 1 only for what no input
// explains (a bug).
#include <filesystem>
#include <iostream>
#include <new>
#include <stdexcept>

#include "core/atomic_file.h"
#include "core/errors.h"
#include "core/exr_io.h"
#include "core/text_limits.h"
#include "glare/wave/psf.h"
#include "glare/wave/psf_scale.h"
#include "runner/cli/commands.h"
#include "runner/devices/hid_device.h"
#include "runner/display/display_backend.h"
#include "runner/session/session_runner.h"
#include "runner/store/result_store.h"
#include "runner/tracker/tracker_source.h"
#include "stimuli/text_image.h"

namespace glarelab::cli {

namespace {

// Messages quote what others wrote (a condition cell, a key, a path): a value of megabytes is cut
// with its length said; control characters are escaped where text reaches the terminal
// (runner/cli/terminal_stream.h) and here too, for callers that print elsewhere.
constexpr std::size_t kMessageBytes = 4000;

int report(const std::string& message, int exit_code) {
  std::cerr << "error: " << shortened_value(message, kMessageBytes, true) << "\n";
  return exit_code;
}

}  // namespace

int report_errors(const std::function<int()>& body) {
  try {
    return body();
  } catch (const ConfigError& error) {
    return report(error.what(), kExitBadInput);
  } catch (const ImageError& error) {
    return report(error.what(), kExitBadInput);
  } catch (const DisplayError& error) {
    return report(error.what(), kExitDevice);
  } catch (const DeviceError& error) {
    return report(error.what(), kExitDevice);
  } catch (const TrackerError& error) {
    return report(error.what(), kExitDevice);
  } catch (const OutputPathError& error) {
    // An output named through a symbolic link: the user's path, not the storage, is refused.
    return report(error.what(), kExitBadInput);
  } catch (const StoreError& error) {
    return report(error.what(), kExitStore);
  } catch (const std::filesystem::filesystem_error& error) {
    // Results folders and output files: the storage could not be written or read.
    return report(error.what(), kExitStore);
  } catch (const PsfScaleError& error) {
    // The glare cannot be sampled at this display's scale: the configuration asks the impossible.
    return report(error.what(), kExitBadInput);
  } catch (const ClosedApertureError& error) {
    return report(error.what(), kExitBadInput);
  } catch (const TextError& error) {
    return report(error.what(), kExitBadInput);
  } catch (const std::invalid_argument& error) {
    // Values the layers below refuse (an option outside what a function can compute).
    return report(error.what(), kExitBadInput);
  } catch (const std::out_of_range& error) {
    return report(error.what(), kExitBadInput);
  } catch (const std::length_error& error) {
    return report(error.what(), kExitBadInput);
  } catch (const std::bad_alloc&) {
    return report("out of memory: the input asks for more memory than this machine has", kExitBadInput);
  } catch (const std::exception& error) {
    return report(std::string("internal error (please report it): ") + error.what(), kExitFailure);
  }
}

}  // namespace glarelab::cli
