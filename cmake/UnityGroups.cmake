# Unity groups: the sources of each layer's library, the benchmarks and the test program compiled a few at a time
# as unity sources, so the headers they share (the standard library, glm, toml++, CLI11, Boost) are
# compiled once per group instead of once per file: most of a cold build's time (README.md, "First
# run"). cmake/unity_groups.py forms the groups: a group never holds two files with the same
# file-local name (each file's anonymous namespace becomes one in a unity source, where same-named
# functions would overload each other silently), a file that defines a macro or has compile options
# or definitions of its own is compiled alone, and a file added after configuring is compiled alone
# until the next configure. The test program's files also name each other's helper names (a local
# kWidth after another file's file-local kWidth is a -Wshadow error in one unity source), so its
# groups also keep apart a file that names another's file-local name (APART_WHEN_NAMED). Before each
# build a check (the same script, the same rule) fails, naming the files and the names, when an
# edit has since brought two such files into one group.
#
# Off (-DGLARELAB_UNITY_GROUPS=OFF) every file compiles on its own: quicker rebuilds while editing
# one file. Without Python 3 or Universal Ctags the option has no effect, and configure says so.
option(GLARELAB_UNITY_GROUPS "Compile each library's, the benchmarks' and the test program's sources as a few unity sources (a quicker cold build)" ON)
# Sixteen: the libraries and glarelab in 42 groups take 542 CPU-s from scratch on two cores, against
# 639 in 58 groups of eight (15 % less), and 32 files no less (36 groups, 556 CPU-s; the last
# groups then leave a core idle); the largest compile holds about 0.85 GB (docs/PERFORMANCE.md,
# "2026-12-01: unity groups of sixteen").
set(GLARELAB_UNITY_GROUP_FILES 16 CACHE STRING "Most source files in one unity group")

if(GLARELAB_UNITY_GROUPS)
  find_program(GLARELAB_CTAGS NAMES ctags-universal universal-ctags ctags)
  find_package(Python3 COMPONENTS Interpreter)
  if(NOT GLARELAB_CTAGS OR NOT Python3_Interpreter_FOUND)
    message(STATUS "Unity groups off: they need python3 and universal-ctags (scripts/setup.sh installs both)")
    set(GLARELAB_UNITY_GROUPS OFF)
  endif()
endif()

# glarelab_unity_groups(target [APART_WHEN_NAMED]): groups the target's own source files (generated
# ones, and files with per-file compile options or definitions, stay alone). APART_WHEN_NAMED: two
# files also stay apart when one names a file-local name the other defines (the test program).
#
# Each group's unity source is written here rather than by CMake's UNITY_BUILD, which names its
# files by their absolute paths: a unity source's text would then differ between two checkouts and
# the compiler cache could never reuse an object compiled in another folder (tests/test_paths.h
# says the same of the test program). Here each file is named relative to the source tree and
# found through the target's include directory (the source tree's root, on every layer's include
# path), so the text is the same in every checkout.
function(glarelab_unity_groups target)
  if(NOT GLARELAB_UNITY_GROUPS)
    return()
  endif()
  cmake_parse_arguments(PARSE_ARGV 1 UNITY "APART_WHEN_NAMED" "" "")
  set(rule "")
  if(UNITY_APART_WHEN_NAMED)
    set(rule --apart-when-named)
  endif()
  get_target_property(sources ${target} SOURCES)
  get_target_property(source_dir ${target} SOURCE_DIR)
  set(candidates "")
  foreach(source IN LISTS sources)
    if(NOT IS_ABSOLUTE "${source}")
      set(source "${source_dir}/${source}")
    endif()
    get_source_file_property(options "${source}" TARGET_DIRECTORY ${target} COMPILE_OPTIONS)
    get_source_file_property(definitions "${source}" TARGET_DIRECTORY ${target} COMPILE_DEFINITIONS)
    if(source MATCHES "\\.cpp$" AND EXISTS "${source}" AND NOT options AND NOT definitions
       AND source MATCHES "^${CMAKE_SOURCE_DIR}/")
      list(APPEND candidates "${source}")
    endif()
  endforeach()
  execute_process(
    COMMAND ${Python3_EXECUTABLE} ${CMAKE_SOURCE_DIR}/cmake/unity_groups.py --ctags ${GLARELAB_CTAGS} ${rule}
            --prefix ${target} --max-files ${GLARELAB_UNITY_GROUP_FILES} ${candidates}
    OUTPUT_VARIABLE lines RESULT_VARIABLE status ERROR_VARIABLE errors)
  if(NOT status EQUAL 0)
    message(FATAL_ERROR "unity groups of ${target}: cmake/unity_groups.py failed: ${errors}")
  endif()
  # Written only when the groups change, as the unity sources below, so that configuring again does
  # not rerun the check below.
  set(groups_file "${CMAKE_BINARY_DIR}/unity_groups/${target}.txt")
  file(CONFIGURE OUTPUT "${groups_file}" CONTENT "${lines}" @ONLY)
  set(grouped "")
  # Each printed line is "name|file|file...".
  file(STRINGS "${groups_file}" group_lines)
  foreach(group_line IN LISTS group_lines)
    string(REPLACE "|" ";" members "${group_line}")
    list(POP_FRONT members group_name)
    set(text "// Unity group ${group_name} (cmake/UnityGroups.cmake, cmake/unity_groups.py).\n")
    foreach(member IN LISTS members)
      file(RELATIVE_PATH relative "${CMAKE_SOURCE_DIR}" "${member}")
      string(APPEND text "#include \"${relative}\"\n")
    endforeach()
    # Written only when the text changes, so that configuring again recompiles nothing.
    set(unity_source "${CMAKE_BINARY_DIR}/unity_groups/${group_name}.cpp")
    file(CONFIGURE OUTPUT "${unity_source}" CONTENT "${text}" @ONLY)
    set_source_files_properties(${members} TARGET_DIRECTORY ${target} PROPERTIES HEADER_FILE_ONLY ON)
    target_sources(${target} PRIVATE "${unity_source}")
    list(APPEND grouped ${members})
  endforeach()
  # gcc warns when a class defined outside the main file has a member of a type from an anonymous
  # namespace, which in a header would break the one-definition rule; in a unity source every file
  # is outside the main file, and the class is still defined in one translation unit only.
  if(CMAKE_CXX_COMPILER_ID STREQUAL "GNU")
    target_compile_options(${target} PRIVATE -Wno-subobject-linkage)
  endif()
  # The check before each build of the target: reruns when any grouped source changes.
  set(stamp "${CMAKE_BINARY_DIR}/unity_groups/${target}.checked")
  add_custom_command(
    OUTPUT "${stamp}"
    COMMAND ${Python3_EXECUTABLE} ${CMAKE_SOURCE_DIR}/cmake/unity_groups.py --ctags ${GLARELAB_CTAGS} ${rule}
            --check "${groups_file}" --stamp "${stamp}"
    DEPENDS ${grouped} "${groups_file}" ${CMAKE_SOURCE_DIR}/cmake/unity_groups.py
    COMMENT "Checking the unity groups of ${target}"
    VERBATIM)
  add_custom_target(${target}_unity_check DEPENDS "${stamp}")
  add_dependencies(${target} ${target}_unity_check)
endfunction()
