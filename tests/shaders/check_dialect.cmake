# The dialect of shaders/common/ (prelude.glsl) has no arrays: lavapipe
# keeps a function's private array in memory, not in registers, and one
# such array (eight normals in svo_sample_shading) made the whole trace
# kernel 2.1x slower there (docs/RESULTS.md, issue 15 round two). This
# check fails on any array declared in a file of the dialect, except the
# members of buffer blocks' structs listed below, which the kernels read
# from their buffers, never copy.
#
#   cmake -DDIR=shaders/common -P check_dialect.cmake
cmake_minimum_required(VERSION 3.20)
if(NOT DIR)
  message(FATAL_ERROR "check_dialect.cmake: give -DDIR=<shaders/common>")
endif()
set(allowed "tracer_params.glsl:light_vector" "tracer_params.glsl:light_radiance")
file(GLOB files "${DIR}/*.glsl" "${DIR}/*.h")
list(LENGTH files count)
if(count EQUAL 0)
  message(FATAL_ERROR "check_dialect.cmake: no files in ${DIR}")
endif()
set(type "(const[ \t]+)?(float|int|uint|bool|[iu]?vec[234]|mat[234]|Svo[A-Za-z0-9_]*)")
set(found 0)
foreach(file IN LISTS files)
  get_filename_component(name "${file}" NAME)
  # One list element per line: CMake lists split at ';' and group by
  # brackets, so both are spelled out first.
  file(READ "${file}" text)
  string(REPLACE ";" "<semicolon>" text "${text}")
  string(REPLACE "[" "<open>" text "${text}")
  string(REPLACE "]" "<close>" text "${text}")
  string(REPLACE "\n" ";" lines "${text}")
  set(n 0)
  foreach(line IN LISTS lines)
    math(EXPR n "${n} + 1")
    if(line MATCHES "^[ \t]*//")
      continue()
    endif()
    if(line MATCHES "^[ \t]*${type}[ \t]+([A-Za-z_][A-Za-z0-9_]*)[ \t]*<open>")
      set(what "${CMAKE_MATCH_3}")
      if(NOT "${name}:${what}" IN_LIST allowed)
        message(SEND_ERROR "${name}:${n}: an array (`${what}`): the dialect has none (prelude.glsl)")
        math(EXPR found "${found} + 1")
      endif()
    endif()
  endforeach()
endforeach()
if(found GREATER 0)
  message(FATAL_ERROR "${found} array(s) in ${DIR}")
endif()
message(STATUS "${count} files of ${DIR}: no arrays")
