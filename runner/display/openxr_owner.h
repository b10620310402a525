#pragma once
// The RAII owner of an OpenXR handle and the zeroed-structure idiom, for runner/display/openxr_session.h
// and openxr_actions.h. Only built where CMake found the loader.
#include <openxr/openxr.h>

#include <utility>

namespace glarelab {

// Owns one OpenXR handle and destroys it with `Destroy` (xrDestroyInstance, ...). Move-only.
template <typename Handle, XrResult (*Destroy)(Handle)>
class XrOwner {
 public:
  XrOwner() = default;
  ~XrOwner() { reset(); }
  XrOwner(XrOwner&& other) noexcept : handle_(std::exchange(other.handle_, XR_NULL_HANDLE)) {}
  XrOwner& operator=(XrOwner&& other) noexcept {
    if (this != &other) {
      reset();
      handle_ = std::exchange(other.handle_, XR_NULL_HANDLE);
    }
    return *this;
  }
  XrOwner(const XrOwner&) = delete;
  XrOwner& operator=(const XrOwner&) = delete;
  Handle get() const { return handle_; }
  Handle* out() {
    reset();
    return &handle_;
  }
  void reset() {
    if (handle_ != XR_NULL_HANDLE) Destroy(handle_);
    handle_ = XR_NULL_HANDLE;
  }

 private:
  Handle handle_ = XR_NULL_HANDLE;
};

// An OpenXR input or output structure with its type set and every other member zero (the `{TYPE}`
// idiom of the specification's examples, without leaving members to aggregate initialisation).
template <typename Struct>
Struct xr_struct(XrStructureType type) {
  Struct value{};
  value.type = type;
  return value;
}

}  // namespace glarelab
