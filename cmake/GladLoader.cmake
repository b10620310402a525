# OpenGL 4.5 core entry points, generated at build time by glad 2 (Debian's python3-glad) from the
# Khronos XML it ships. The loader takes a get-proc-address function, so each display backend
# (OSMesaGetProcAddress, glfwGetProcAddress, later eglGetProcAddress) loads the same table and no
# code calls libGL's exported symbols directly (libGL and libOSMesa both export gl*).
find_program(GLARELAB_SYSTEM_PYTHON python3 PATHS /usr/bin NO_DEFAULT_PATH REQUIRED)
set(GLAD_OUT ${CMAKE_BINARY_DIR}/glad)
add_custom_command(
  OUTPUT ${GLAD_OUT}/src/gl.c ${GLAD_OUT}/include/glad/gl.h
  COMMAND ${GLARELAB_SYSTEM_PYTHON} -m glad --quiet --reproducible --api gl:core=4.5
          --extensions "" --out-path ${GLAD_OUT} c
  COMMENT "Generating the OpenGL 4.5 core loader with glad"
  VERBATIM)
add_library(glarelab_glad STATIC ${GLAD_OUT}/src/gl.c)
target_include_directories(glarelab_glad SYSTEM PUBLIC ${GLAD_OUT}/include)
set_target_properties(glarelab_glad PROPERTIES POSITION_INDEPENDENT_CODE ON)
