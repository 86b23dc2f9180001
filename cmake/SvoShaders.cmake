# svo_add_shader_library(TARGET SOURCES <file.comp>...)
#
# Compiles each GLSL source to SPIR-V with glslangValidator at build time
# (Vulkan 1.1 target, #include dependencies tracked through a depfile) and
# embeds the words in a generated header <name>.spv.h that declares
#   const uint32_t svo_spv_<name>[]
# where <name> is the file name with '.' replaced by '_'. TARGET is an
# INTERFACE library whose include path holds the generated headers.
function(svo_add_shader_library target)
  cmake_parse_arguments(ARG "" "" "SOURCES" ${ARGN})
  set(out_dir "${CMAKE_CURRENT_BINARY_DIR}/spv")
  file(MAKE_DIRECTORY "${out_dir}")
  set(headers)
  foreach(src IN LISTS ARG_SOURCES)
    get_filename_component(abs_src "${src}" ABSOLUTE)
    get_filename_component(name "${src}" NAME)
    string(REPLACE "." "_" var "${name}")
    set(header "${out_dir}/${name}.spv.h")
    add_custom_command(
      OUTPUT "${header}"
      COMMAND "${GLSLANG_VALIDATOR}" --target-env vulkan1.1 --quiet
              -I${PROJECT_SOURCE_DIR}/shaders
              --depfile "${header}.d"
              --vn "svo_spv_${var}"
              -o "${header}" "${abs_src}"
      DEPENDS "${abs_src}"
      DEPFILE "${header}.d"
      COMMENT "GLSL -> SPIR-V ${name}"
      VERBATIM)
    list(APPEND headers "${header}")
  endforeach()
  add_custom_target(${target}_compile DEPENDS ${headers})
  add_library(${target} INTERFACE)
  add_dependencies(${target} ${target}_compile)
  target_include_directories(${target} INTERFACE "${out_dir}")
endfunction()
