# nhc_add_model(<target> <scene> [MODEL <model>] [JACOBIAN dense|sparse|none]
#               [OUTPUT_DIR <dir>] [OUT_VAR <variable>])
#
# Generates the C++ header of one model of a scene at build time (`nhc generate`, layout in
# docs/generated-code.md) and adds it to <target>: the header becomes one of the target's
# sources and its directory one of its include directories, so that the target writes
#   #include "<name>_<model>.hpp"        // namespace nhc_gen::<name>_<model>
# and links nhc::runtime to integrate it (docs/runtime.md).
#
# Like protobuf_generate(), the header is the OUTPUT of a custom command that DEPENDS on the scene
# file and on the nhc executable: editing the scene (or rebuilding nhc) regenerates it at the next
# build. The scene is also a configure dependency, because the header's file name comes from the
# scene's `name` and default model, which are read here.
#
#   MODEL       vakonomic | chetaev | holder | suslov; default as `nhc generate`: the scene's
#               [simulate] model, else chetaev when the scene lists it, else its first model.
#   JACOBIAN    dense (default), sparse (compressed column) or none.
#   OUTPUT_DIR  where the header is written; default ${CMAKE_CURRENT_BINARY_DIR}/nhc_models/<target>.
#   OUT_VAR     set to the header's full path in the caller's scope.
#
# Call it in the directory that defines <target> (custom-command outputs are local to a
# directory). Works with the installed package (find_package(nhc)) and inside nhc's own build,
# where it uses the executable target nhc::nhc either way.
include_guard(GLOBAL)

# Reads `name` and the default model from a scene file without a TOML parser: `name = "…"` in
# the top-level part, `model = "…"` in [simulate], and a `models = [...]` list.
function(_nhc_scene_defaults scene out_name out_model)
  file(READ "${scene}" text)
  string(REPLACE "\r" "" text "\n${text}")
  # Top-level keys come before the first table header.
  set(top "${text}")
  string(REGEX MATCH "\n[ \t]*\\[" header "${text}")
  if(header)
    string(FIND "${text}" "${header}" start)
    string(SUBSTRING "${text}" 0 ${start} top)
  endif()
  string(REGEX MATCH "\n[ \t]*name[ \t]*=[ \t]*\"([A-Za-z_][A-Za-z0-9_]*)\"" match "${top}")
  if(NOT match)
    message(FATAL_ERROR "nhc_add_model: cannot find the scene name in ${scene}; "
                        "write it on one line, `name = \"identifier\"`, before any [table]")
  endif()
  set(${out_name} "${CMAKE_MATCH_1}" PARENT_SCOPE)

  set(models "")
  if(top MATCHES "\n[ \t]*models[ \t]*=[ \t]*\\[([^]]*)\\]")
    string(REGEX MATCHALL "[a-z]+" models "${CMAKE_MATCH_1}")
  endif()
  set(model "")
  if(text MATCHES "\n[ \t]*\\[[ \t]*simulate[ \t]*\\][^\n]*(.*)")
    set(section "${CMAKE_MATCH_1}")
    string(REGEX MATCH "\n[ \t]*\\[" next "${section}")
    if(next)
      string(FIND "${section}" "${next}" end)
      string(SUBSTRING "${section}" 0 ${end} section)
    endif()
    if(section MATCHES "\n[ \t]*model[ \t]*=[ \t]*\"([a-z]+)\"")
      set(model "${CMAKE_MATCH_1}")
    endif()
  endif()
  if(NOT model)
    list(FIND models chetaev chetaev_at)  # not IN_LIST: callers may run under old policies
    if(NOT models OR NOT chetaev_at EQUAL -1)
      set(model chetaev)
    else()
      list(GET models 0 model)
    endif()
  endif()
  set(${out_model} "${model}" PARENT_SCOPE)
endfunction()

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
  set_property(DIRECTORY APPEND PROPERTY CMAKE_CONFIGURE_DEPENDS "${scene}")

  _nhc_scene_defaults("${scene}" name default_model)
  set(model "${default_model}")
  if(arg_MODEL)
    set(model "${arg_MODEL}")
  endif()
  if(NOT model MATCHES "^(vakonomic|chetaev|holder|suslov)$")
    message(FATAL_ERROR "nhc_add_model: unknown MODEL '${model}' "
                        "(known: vakonomic, chetaev, holder, suslov)")
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
  set(header "${dir}/${name}_${model}.hpp")
  get_filename_component(scene_file "${scene}" NAME)

  add_custom_command(
    OUTPUT "${header}"
    COMMAND nhc::nhc generate "${scene}" --model ${model} --jacobian ${jacobian} --quiet
            -o "${dir}"
    DEPENDS "${scene}" nhc::nhc
    COMMENT "nhc: generating ${name}_${model}.hpp from ${scene_file}"
    VERBATIM)
  target_sources(${target} PRIVATE "${header}")
  get_target_property(type ${target} TYPE)
  if(type STREQUAL "EXECUTABLE")
    target_include_directories(${target} PRIVATE "${dir}")
  else()
    target_include_directories(${target} PUBLIC "$<BUILD_INTERFACE:${dir}>")
  endif()
  if(arg_OUT_VAR)
    set(${arg_OUT_VAR} "${header}" PARENT_SCOPE)
  endif()
endfunction()
