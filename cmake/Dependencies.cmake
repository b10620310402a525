# System libraries, all from Debian packages installed by scripts/setup.sh.
find_package(PkgConfig REQUIRED)
find_package(Threads REQUIRED)
find_package(OpenEXR 3 CONFIG REQUIRED)
find_package(glfw3 3.3 CONFIG REQUIRED)
find_package(tomlplusplus CONFIG QUIET)
find_package(CLI11 CONFIG REQUIRED)
pkg_check_modules(OSMESA REQUIRED IMPORTED_TARGET osmesa)
pkg_check_modules(SQLITE3 REQUIRED IMPORTED_TARGET sqlite3)
pkg_check_modules(PNG REQUIRED IMPORTED_TARGET libpng)
pkg_check_modules(FFTW3 REQUIRED IMPORTED_TARGET fftw3)

if(NOT EXISTS /usr/include/Random123/philox.h)
  message(FATAL_ERROR "Random123 headers not found: install librandom123-dev (scripts/setup.sh does)")
endif()
if(NOT EXISTS /usr/include/toml++/toml.h AND NOT TARGET tomlplusplus::tomlplusplus)
  message(FATAL_ERROR "toml++ not found: install libtomlplusplus-dev (scripts/setup.sh does)")
endif()

add_library(glarelab_deps INTERFACE)
target_link_libraries(glarelab_deps INTERFACE
  OpenEXR::OpenEXR glfw CLI11::CLI11 PkgConfig::OSMESA PkgConfig::SQLITE3 PkgConfig::PNG PkgConfig::FFTW3
  Threads::Threads ${CMAKE_DL_LIBS})
if(TARGET tomlplusplus::tomlplusplus)
  target_link_libraries(glarelab_deps INTERFACE tomlplusplus::tomlplusplus)
endif()
