// The one place error types become exit codes (README "Exit codes"): 2 for input that cannot be
// used, 3 for a display, GL or device that cannot deliver, 4 for storage; 1 only for what no input
// explains (a bug).
#include <filesystem>
#include <iostream>
#include <new>
#include <stdexcept>

#include "core/errors.h"
#include "core/exr_io.h"
#include "glare/psf.h"
#include "glare/psf_scale.h"
#include "runner/cli/commands.h"
#include "runner/devices/hid_device.h"
#include "runner/display/display_backend.h"
#include "runner/session/session_runner.h"
#include "runner/store/result_store.h"
#include "runner/tracker/tracker_source.h"
#include "stimuli/text_image.h"

namespace glarelab::cli {

int report_errors(const std::function<int()>& body) {
  try {
    return body();
  } catch (const ConfigError& error) {
    std::cerr << "error: " << error.what() << "\n";
    return kExitBadInput;
  } catch (const ImageError& error) {
    std::cerr << "error: " << error.what() << "\n";
    return kExitBadInput;
  } catch (const DisplayError& error) {
    std::cerr << "error: " << error.what() << "\n";
    return kExitDevice;
  } catch (const DeviceError& error) {
    std::cerr << "error: " << error.what() << "\n";
    return kExitDevice;
  } catch (const TrackerError& error) {
    std::cerr << "error: " << error.what() << "\n";
    return kExitDevice;
  } catch (const StoreError& error) {
    std::cerr << "error: " << error.what() << "\n";
    return kExitStore;
  } catch (const std::filesystem::filesystem_error& error) {
    // Results folders and output files: the storage could not be written or read.
    std::cerr << "error: " << error.what() << "\n";
    return kExitStore;
  } catch (const PsfScaleError& error) {
    // The glare cannot be sampled at this display's scale: the configuration asks the impossible.
    std::cerr << "error: " << error.what() << "\n";
    return kExitBadInput;
  } catch (const ClosedApertureError& error) {
    std::cerr << "error: " << error.what() << "\n";
    return kExitBadInput;
  } catch (const TextError& error) {
    std::cerr << "error: " << error.what() << "\n";
    return kExitBadInput;
  } catch (const std::invalid_argument& error) {
    // Values the layers below refuse (an option outside what a function can compute).
    std::cerr << "error: " << error.what() << "\n";
    return kExitBadInput;
  } catch (const std::out_of_range& error) {
    std::cerr << "error: " << error.what() << "\n";
    return kExitBadInput;
  } catch (const std::length_error& error) {
    std::cerr << "error: " << error.what() << "\n";
    return kExitBadInput;
  } catch (const std::bad_alloc&) {
    std::cerr << "error: out of memory: the input asks for more memory than this machine has\n";
    return kExitBadInput;
  } catch (const std::exception& error) {
    std::cerr << "error: internal error (please report it): " << error.what() << "\n";
    return kExitFailure;
  }
}

}  // namespace glarelab::cli
