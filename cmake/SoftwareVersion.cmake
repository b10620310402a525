# The git revision goes into every session row (sessions.software_version). It is re-read on every
# build, so a rebuild after a commit records the new revision; "-dirty" marks uncommitted changes.
set(GLARELAB_VERSION_SOURCE ${CMAKE_BINARY_DIR}/generated/software_version.cpp)
execute_process(COMMAND ${CMAKE_COMMAND} -DSOURCE_DIR=${CMAKE_SOURCE_DIR} -DOUT=${GLARELAB_VERSION_SOURCE}
  -DPROJECT_VERSION=${PROJECT_VERSION} -P ${CMAKE_SOURCE_DIR}/cmake/WriteVersion.cmake)
add_custom_target(glarelab_version_stamp
  COMMAND ${CMAKE_COMMAND} -DSOURCE_DIR=${CMAKE_SOURCE_DIR} -DOUT=${GLARELAB_VERSION_SOURCE}
          -DPROJECT_VERSION=${PROJECT_VERSION} -P ${CMAKE_SOURCE_DIR}/cmake/WriteVersion.cmake
  BYPRODUCTS ${GLARELAB_VERSION_SOURCE}
  COMMENT "Recording the git revision")
