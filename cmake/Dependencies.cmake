# System libraries, all from Debian packages installed by scripts/setup.sh.
find_package(PkgConfig REQUIRED)
find_package(Threads REQUIRED)
# Debian 12's Imath package config lists its Python module (libPyImath_Python3_11), which lives in
# another package, and reports the missing file as a status message on every configure. glarelab
# does not use it, so that one lookup runs with status messages quieted.
set(glarelab_message_log_level "${CMAKE_MESSAGE_LOG_LEVEL}")
set(CMAKE_MESSAGE_LOG_LEVEL NOTICE)
find_package(OpenEXR 3 CONFIG REQUIRED)
set(CMAKE_MESSAGE_LOG_LEVEL "${glarelab_message_log_level}")
find_package(glfw3 3.3 CONFIG REQUIRED)
find_package(tomlplusplus CONFIG QUIET)
find_package(CLI11 CONFIG REQUIRED)
pkg_check_modules(OSMESA REQUIRED IMPORTED_TARGET osmesa)
pkg_check_modules(EGL REQUIRED IMPORTED_TARGET egl)  # libegl-dev: headless GL beside OSMesa
pkg_check_modules(SQLITE3 REQUIRED IMPORTED_TARGET sqlite3)
pkg_check_modules(PNG REQUIRED IMPORTED_TARGET libpng)
# FFTW3 double (reference) and float (speed) FFTs, with their thread libraries (libfftw3-dev).
pkg_check_modules(FFTW3 REQUIRED IMPORTED_TARGET fftw3)
pkg_check_modules(FFTW3F REQUIRED IMPORTED_TARGET fftw3f)
# The planned float path runs its transforms on FFTW's threads (glare/cpu/fftw_float_plan.h); pkg-config
# does not name the thread library, which the same package installs beside libfftw3f.
find_library(FFTW3F_THREADS_LIBRARY fftw3f_threads HINTS ${FFTW3F_LIBRARY_DIRS} REQUIRED)
# Analysis: Boost.Math distributions (header-only), NLopt for maximum-likelihood fits,
# nlohmann JSON for the trials.condition column.
find_package(Boost 1.74 REQUIRED)
find_package(glm CONFIG REQUIRED)
find_package(nlohmann_json 3 CONFIG REQUIRED)
find_package(NLopt CONFIG REQUIRED)

if(NOT EXISTS /usr/include/Random123/philox.h)
  message(FATAL_ERROR "Random123 headers not found: install librandom123-dev (scripts/setup.sh does)")
endif()
if(NOT EXISTS /usr/include/toml++/toml.h AND NOT TARGET tomlplusplus::tomlplusplus)
  message(FATAL_ERROR "toml++ not found: install libtomlplusplus-dev (scripts/setup.sh does)")
endif()

# One interface target per layer, holding only the libraries that layer uses (docs/ARCHITECTURE.md).
# core: images and their files, random numbers, GL owners.
add_library(glarelab_deps_core INTERFACE)
target_link_libraries(glarelab_deps_core INTERFACE OpenEXR::OpenEXR PkgConfig::PNG Threads::Threads ${CMAKE_DL_LIBS})
# glare: the CPU FFTs, GLM geometry, Boost.Math quadrature.
add_library(glarelab_deps_glare INTERFACE)
target_link_libraries(glarelab_deps_glare INTERFACE ${FFTW3F_THREADS_LIBRARY} PkgConfig::FFTW3 PkgConfig::FFTW3F Threads::Threads
                      glm::glm Boost::headers)
# protocols: experiment files.
add_library(glarelab_deps_protocols INTERFACE)
if(TARGET tomlplusplus::tomlplusplus)
  target_link_libraries(glarelab_deps_protocols INTERFACE tomlplusplus::tomlplusplus)
endif()
# analysis: databases read-only, distributions, fits, JSON conditions.
add_library(glarelab_deps_analysis INTERFACE)
target_link_libraries(glarelab_deps_analysis INTERFACE
  PkgConfig::SQLITE3 Boost::headers nlohmann_json::nlohmann_json NLopt::nlopt)
# The stored configuration (TOML) is read for the observer's eye (analysis/session_observer_eye.h).
if(TARGET tomlplusplus::tomlplusplus)
  target_link_libraries(glarelab_deps_analysis INTERFACE tomlplusplus::tomlplusplus)
endif()
# runner: displays, command line, the store, trackers and devices (below).
add_library(glarelab_deps_runner INTERFACE)
# OSMesa's header only: runner/display/osmesa_display.cpp opens libOSMesa when it is first needed
# (it loads libLLVM, a cost every process paid at start when it was linked).
target_include_directories(glarelab_deps_runner INTERFACE ${OSMESA_INCLUDE_DIRS})
target_link_libraries(glarelab_deps_runner INTERFACE glfw CLI11::CLI11 PkgConfig::EGL PkgConfig::SQLITE3 ${CMAKE_DL_LIBS})

# OpenXR (libopenxr-dev; docs/STEREO.md): the headset display links the loader only where it is
# found, with GLX and Xlib for the OpenGL binding on X11; elsewhere `--display openxr` exits 3 saying so.
# The answer is one generated header, read only by the OpenXR display's sources and tests.
find_package(OpenXR CONFIG QUIET)
find_package(OpenGL QUIET COMPONENTS GLX)
find_package(X11 QUIET)
if(OpenXR_FOUND AND TARGET OpenGL::GLX AND TARGET X11::X11)
  target_link_libraries(glarelab_deps_runner INTERFACE OpenXR::openxr_loader OpenGL::GLX X11::X11)
  set(GLARELAB_HAVE_OPENXR 1)
else()
  message(STATUS "OpenXR loader not found (libopenxr-dev): --display openxr will say so and exit 3")
  set(GLARELAB_HAVE_OPENXR 0)
endif()
file(CONFIGURE OUTPUT ${CMAKE_BINARY_DIR}/generated/openxr_available.h
     CONTENT "#pragma once\n#define GLARELAB_HAVE_OPENXR ${GLARELAB_HAVE_OPENXR}\n")

# Eye trackers and response devices (runner/tracker, runner/devices): ZeroMQ (Pupil Core network
# API) with cppzmq, msgpack-cxx header-only without Boost, hidapi (hidraw backend), libusb.
pkg_check_modules(ZMQ REQUIRED IMPORTED_TARGET libzmq)
pkg_check_modules(HIDAPI REQUIRED IMPORTED_TARGET hidapi-hidraw)
pkg_check_modules(LIBUSB REQUIRED IMPORTED_TARGET libusb-1.0)
if(NOT EXISTS /usr/include/zmq.hpp)
  message(FATAL_ERROR "cppzmq not found: install cppzmq-dev (scripts/setup.sh does)")
endif()
if(NOT EXISTS /usr/include/msgpack.hpp)
  message(FATAL_ERROR "msgpack-cxx not found: install libmsgpack-cxx-dev (scripts/setup.sh does)")
endif()
target_link_libraries(glarelab_deps_runner INTERFACE PkgConfig::ZMQ PkgConfig::HIDAPI PkgConfig::LIBUSB)
target_compile_definitions(glarelab_deps_runner INTERFACE MSGPACK_NO_BOOST)

# On-screen text (stimuli/text_image.*): FreeType rasterises DejaVu Sans, a font every Debian
# system can have (fonts-dejavu-core); the file is fixed here so text looks the same everywhere.
find_package(Freetype REQUIRED)
set(GLARELAB_FONT_FILE "/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf" CACHE FILEPATH
    "TrueType font for instruction and message screens")
if(NOT EXISTS "${GLARELAB_FONT_FILE}")
  message(FATAL_ERROR "${GLARELAB_FONT_FILE} not found: install fonts-dejavu-core (scripts/setup.sh does)")
endif()
add_library(glarelab_deps_stimuli INTERFACE)
target_link_libraries(glarelab_deps_stimuli INTERFACE Freetype::Freetype)
target_compile_definitions(glarelab_deps_stimuli INTERFACE GLARELAB_FONT_FILE="${GLARELAB_FONT_FILE}")
