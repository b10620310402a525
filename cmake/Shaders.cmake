# Shaders are files beside the code that uses them (*.vert, *.frag, *.comp). Each is validated at
# build time by glslangValidator (Debian's glslang-tools) as OpenGL GLSL, and all are embedded into
# the binary, so a broken shader fails the build rather than a session, and no run reads shader
# files from disk.
find_program(GLSLANG_VALIDATOR glslangValidator REQUIRED)
file(GLOB_RECURSE GLARELAB_SHADER_FILES CONFIGURE_DEPENDS
  ${CMAKE_SOURCE_DIR}/core/*.vert ${CMAKE_SOURCE_DIR}/core/*.frag ${CMAKE_SOURCE_DIR}/core/*.comp
  ${CMAKE_SOURCE_DIR}/runner/*.vert ${CMAKE_SOURCE_DIR}/runner/*.frag ${CMAKE_SOURCE_DIR}/runner/*.comp
  ${CMAKE_SOURCE_DIR}/stimuli/*.vert ${CMAKE_SOURCE_DIR}/stimuli/*.frag ${CMAKE_SOURCE_DIR}/stimuli/*.comp
  ${CMAKE_SOURCE_DIR}/glare/*.vert ${CMAKE_SOURCE_DIR}/glare/*.frag ${CMAKE_SOURCE_DIR}/glare/*.comp)

file(MAKE_DIRECTORY ${CMAKE_BINARY_DIR}/shader_checks ${CMAKE_BINARY_DIR}/generated)
set(GLARELAB_SHADER_STAMPS)
foreach(shader ${GLARELAB_SHADER_FILES})
  file(RELATIVE_PATH rel ${CMAKE_SOURCE_DIR} ${shader})
  string(REPLACE "/" "_" stamp_name ${rel})
  set(stamp ${CMAKE_BINARY_DIR}/shader_checks/${stamp_name}.ok)
  set(validations COMMAND ${GLSLANG_VALIDATOR} ${shader})
  if(rel STREQUAL "stimuli/shaders/encode_display.frag")
    # Built once per encoding and dithering (stimuli/frame_renderer.cpp): each pair is validated.
    set(validations)
    foreach(encoding 0 1 2)
      foreach(dither 0 1)
        list(APPEND validations COMMAND ${GLSLANG_VALIDATOR} -l -DENCODING=${encoding} -DDITHER=${dither} ${shader})
      endforeach()
    endforeach()
  endif()
  add_custom_command(OUTPUT ${stamp}
    ${validations}
    COMMAND ${CMAKE_COMMAND} -E touch ${stamp}
    DEPENDS ${shader}
    COMMENT "Validating shader ${rel}"
    VERBATIM)
  list(APPEND GLARELAB_SHADER_STAMPS ${stamp})
endforeach()
add_custom_target(glarelab_shaders_validated DEPENDS ${GLARELAB_SHADER_STAMPS})

set(GLARELAB_SHADER_SOURCE ${CMAKE_BINARY_DIR}/generated/embedded_shaders.cpp)
add_custom_command(OUTPUT ${GLARELAB_SHADER_SOURCE}
  COMMAND ${CMAKE_COMMAND} -DSOURCE_DIR=${CMAKE_SOURCE_DIR} -DOUT=${GLARELAB_SHADER_SOURCE}
          "-DSHADERS=${GLARELAB_SHADER_FILES}" -P ${CMAKE_SOURCE_DIR}/cmake/EmbedShaders.cmake
  DEPENDS ${GLARELAB_SHADER_FILES} ${CMAKE_SOURCE_DIR}/cmake/EmbedShaders.cmake
  COMMENT "Embedding shaders"
  VERBATIM)
