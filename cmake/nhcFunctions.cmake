# nhc_add_model(<target> <scene> [MODEL <model>] [JACOBIAN dense|sparse|none]
#               [OUTPUT_DIR <dir>] [OUT_VAR <variable>])
#
# Generates the C++ header of one model of a scene at build time (`nhc generate`, layout in
# docs/generated-code.md) and adds it to <target>: the header becomes one of the target's
# sources and its directory one of its include directories, so that the target writes
#   #include "<name>_<model>.hpp"        // namespace nhc_gen::<name>_<model>
# and links nhc::runtime to integrate it (docs/runtime.md).
#
# The header is made by a custom command that DEPENDS on the scene file and on the nhc executable:
# editing the scene (or rebuilding nhc) regenerates it at the next build, and <target> is built
# after it. CMake never reads the scene: the header's name and the default model are nhc's
# decisions (`nhc generate`), made when it runs. Its OUTPUT is therefore a stamp file beside the
# header, and the compiler's dependency scan ties the sources to the header itself.
#
#   MODEL       vakonomic | chetaev | holder | suslov; default as `nhc generate`: the scene's
#               [simulate] model, else chetaev when the scene lists it, else its first model.
#   JACOBIAN    dense (default), sparse (compressed column) or none.
#   OUTPUT_DIR  where the header is written; default ${CMAKE_CURRENT_BINARY_DIR}/nhc_models/<target>.
#   OUT_VAR     set to the header's full path in the caller's scope. The name is asked of nhc at
#               configure time (`nhc generate --print-file-name`), so OUT_VAR needs an nhc
#               executable then: the installed package's; inside nhc's own build it is an error.
#
# Call it in the directory that defines <target>. Works with the installed package
# (find_package(nhc)) and inside nhc's own build, where it uses the executable target nhc::nhc
# either way.
include_guard(GLOBAL)

function(nhc_add_model target scene)
  cmake_parse_arguments(PARSE_ARGV 2 arg "" "MODEL;JACOBIAN;OUTPUT_DIR;OUT_VAR" "")
  if(arg_UNPARSED_ARGUMENTS)
    message(FATAL_ERROR "nhc_add_model: unexpected arguments: ${arg_UNPARSED_ARGUMENTS}")
  endif()
  if(NOT TARGET ${target})
    message(FATAL_ERROR "nhc_add_model: ${target} is not a target")
  endif()
  if(NOT TARGET nhc::nhc)
    message(FATAL_ERROR "nhc_add_model: the nhc executable (target nhc::nhc) is not known; "
                        "call find_package(nhc) first")
  endif()
  get_filename_component(scene "${scene}" ABSOLUTE BASE_DIR "${CMAKE_CURRENT_SOURCE_DIR}")
  if(NOT EXISTS "${scene}")
    message(FATAL_ERROR "nhc_add_model: scene file ${scene} does not exist")
  endif()

  set(model_option "")
  set(model_words "default model")
  if(arg_MODEL)
    set(model_option --model ${arg_MODEL})
    set(model_words "${arg_MODEL} model")
  endif()
  set(jacobian dense)
  if(arg_JACOBIAN)
    set(jacobian "${arg_JACOBIAN}")
  endif()
  if(NOT jacobian MATCHES "^(dense|sparse|none)$")
    message(FATAL_ERROR "nhc_add_model: JACOBIAN must be dense, sparse or none, not '${jacobian}'")
  endif()
  set(dir "${CMAKE_CURRENT_BINARY_DIR}/nhc_models/${target}")
  if(arg_OUTPUT_DIR)
    get_filename_component(dir "${arg_OUTPUT_DIR}" ABSOLUTE BASE_DIR "${CMAKE_CURRENT_BINARY_DIR}")
  endif()
  get_filename_component(scene_file "${scene}" NAME)
  get_filename_component(scene_stem "${scene}" NAME_WE)
  string(MAKE_C_IDENTIFIER "${scene_stem}" scene_stem)
  string(MD5 call_key "${scene};${arg_MODEL};${jacobian};${dir}")
  string(SUBSTRING "${call_key}" 0 8 call_key)
  set(stamp "${dir}/.${scene_stem}-${call_key}.stamp")

  add_custom_command(
    OUTPUT "${stamp}"
    COMMAND nhc::nhc generate "${scene}" ${model_option} --jacobian ${jacobian} --quiet -o "${dir}"
    COMMAND ${CMAKE_COMMAND} -E touch "${stamp}"
    DEPENDS "${scene}" nhc::nhc
    COMMENT "nhc: generating the ${model_words} of ${scene_file}"
    VERBATIM)
  set(generator_target "${target}_nhc_${scene_stem}_${call_key}")
  add_custom_target(${generator_target} DEPENDS "${stamp}")
  add_dependencies(${target} ${generator_target})
  get_target_property(type ${target} TYPE)
  if(type STREQUAL "EXECUTABLE")
    target_include_directories(${target} PRIVATE "${dir}")
  else()
    target_include_directories(${target} PUBLIC "$<BUILD_INTERFACE:${dir}>")
  endif()
  if(arg_OUT_VAR)
    get_target_property(imported nhc::nhc IMPORTED)
    if(NOT imported)
      message(FATAL_ERROR "nhc_add_model: OUT_VAR needs the installed nhc (the header's name is "
                          "asked of the nhc executable at configure time; here it is not built yet)")
    endif()
    get_target_property(nhc_executable nhc::nhc LOCATION)
    execute_process(
      COMMAND "${nhc_executable}" generate "${scene}" ${model_option} --print-file-name
      OUTPUT_VARIABLE file_name ERROR_VARIABLE error RESULT_VARIABLE status
      OUTPUT_STRIP_TRAILING_WHITESPACE ERROR_STRIP_TRAILING_WHITESPACE)
    if(NOT status EQUAL 0)
      message(FATAL_ERROR "nhc_add_model: ${error}")
    endif()
    set_property(DIRECTORY APPEND PROPERTY CMAKE_CONFIGURE_DEPENDS "${scene}" "${nhc_executable}")
    set(${arg_OUT_VAR} "${dir}/${file_name}" PARENT_SCOPE)
  endif()
endfunction()
