// The one place error types become exit codes (README "Exit codes"): 2 for input that cannot be
// used, 3 for a display, GL or device that cannot deliver, 4 for storage; 1 only for what no input
// explains (a bug).
#include <filesystem>
#include <iostream>
#include <new>
#include <stdexcept>

#include "core/errors.h"
#include "core/exr_io.h"
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

int report(const std::string& message, int exit_code) {
  std::cerr << "error: " << message << "\n";
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
