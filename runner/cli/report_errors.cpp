#include <iostream>

#include "core/errors.h"
#include "runner/cli/commands.h"
#include "runner/devices/hid_device.h"
#include "runner/display/display_backend.h"
#include "runner/session/session_runner.h"
#include "runner/store/result_store.h"
#include "runner/tracker/tracker_source.h"
#include "core/exr_io.h"

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
  } catch (const std::exception& error) {
    std::cerr << "error: " << error.what() << "\n";
    return kExitFailure;
  }
}

}  // namespace glarelab::cli
