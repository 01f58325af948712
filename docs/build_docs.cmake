# The steps of the target `docs` (docs/CMakeLists.txt):
#   1. copy docs/ to WORK_DIR/src (the sources stay the only copy) and the example notebooks to
#      WORK_DIR/src/tutorials; WORK_DIR/examples links to the source tree's examples/, since a
#      notebook finds its scenes two directories above itself, as in examples/notebooks;
#   2. write the page commands-help.md from `nhc --help` and `nhc <command> --help` (the command
#      line's own help text, so the page cannot drift from it), and scene-keys.md from the scene
#      loader's own lists of keys (docs/scene_keys.py, which fails on a key scenes.md misses), and
#      cpp-api.md from the installed headers of the runtime and the jit (docs/cpp_api.py);
#   3. sphinx-build -W (every warning an error) -E (every page again: a notebook's outputs depend on
#      the built module, which Sphinx does not see change), notebooks executed against the built module;
#   4. MathJax from Debian's libjs-mathjax beside the pages (the site works offline).
# usage: cmake -DSOURCE_DIR= -DWORK_DIR= -DNHC= -DPYTHON= -DPYTHON_DIR= -DSPHINX= -DVERSION= -P build_docs.cmake
cmake_minimum_required(VERSION 3.20)
foreach(var SOURCE_DIR WORK_DIR NHC PYTHON PYTHON_DIR SPHINX VERSION)
  if(NOT DEFINED ${var})
    message(FATAL_ERROR "build_docs.cmake: -D${var}=… is required")
  endif()
endforeach()
set(src ${WORK_DIR}/src)
file(REMOVE_RECURSE ${src})
file(COPY ${SOURCE_DIR}/docs/ DESTINATION ${src}
  PATTERN CMakeLists.txt EXCLUDE PATTERN "*.cmake" EXCLUDE PATTERN "*.py" EXCLUDE)
file(COPY ${SOURCE_DIR}/docs/conf.py DESTINATION ${src})
file(GLOB notebooks ${SOURCE_DIR}/examples/notebooks/*.ipynb)
file(COPY ${notebooks} DESTINATION ${src}/tutorials)
file(REMOVE ${WORK_DIR}/examples)
file(CREATE_LINK ${SOURCE_DIR}/examples ${WORK_DIR}/examples SYMBOLIC)

# 2. The command line's help, command by command, in the order `nhc --help` lists them.
execute_process(COMMAND ${NHC} --help OUTPUT_VARIABLE top RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "nhc --help failed (${rc})")
endif()
string(REGEX REPLACE "Usage: [^ ]*nhc" "Usage: nhc" top "${top}")
set(page "# Command-line help\n\nGenerated at every docs build from `nhc --help` and `nhc <command> --help` "
  "(docs/build_docs.cmake): the flags exactly as the command line states them. What the commands do is on the "
  "[command reference](commands.md).\n\n```text\n${top}```\n")
string(REGEX MATCH "Subcommands:\n.*" listing "${top}")
string(REGEX MATCHALL "\n  [a-z]+ " names "${listing}")
set(count 0)
foreach(name IN LISTS names)
  string(STRIP "${name}" name)
  execute_process(COMMAND ${NHC} ${name} --help OUTPUT_VARIABLE help RESULT_VARIABLE rc)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "nhc ${name} --help failed (${rc})")
  endif()
  string(REGEX REPLACE "Usage: [^ ]*nhc" "Usage: nhc" help "${help}")
  string(APPEND page "\n## nhc ${name}\n\n```text\n${help}```\n")
  math(EXPR count "${count} + 1")
endforeach()
if(count LESS 5)
  message(FATAL_ERROR "nhc --help listed only ${count} commands")
endif()
file(WRITE ${src}/commands-help.md "${page}")
execute_process(COMMAND ${PYTHON} ${SOURCE_DIR}/docs/scene_keys.py page --nhc ${NHC} --docs ${SOURCE_DIR}/docs
                        --out ${src}/scene-keys.md
                RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "docs/scene_keys.py failed (${rc})")
endif()
execute_process(COMMAND ${PYTHON} ${SOURCE_DIR}/docs/cpp_api.py --source ${SOURCE_DIR} --out ${src}/cpp-api.md
                RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "docs/cpp_api.py failed (${rc})")
endif()

# 3. Sphinx.
execute_process(
  COMMAND ${CMAKE_COMMAND} -E env NHC_PYTHON_DIR=${PYTHON_DIR} PYTHONPATH=${PYTHON_DIR} NHC_VERSION=${VERSION}
          NHC_EXECUTABLE=${NHC}
          NHC_CACHE_DIR=${WORK_DIR}/nhc-cache PYDEVD_DISABLE_FILE_VALIDATION=1 PATH=${WORK_DIR}/bin:$ENV{PATH}
          ${SPHINX} -W --keep-going -q -E -b html -d ${WORK_DIR}/doctrees ${src} ${WORK_DIR}/html
  RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "sphinx-build failed (${rc})")
endif()

# 4. MathJax 2 from /usr/share/javascript/mathjax (conf.py: mathjax_path), without its tests and
#    unpacked sources.
set(mathjax /usr/share/javascript/mathjax)
if(NOT EXISTS ${mathjax}/MathJax.js)
  message(FATAL_ERROR "${mathjax}/MathJax.js is missing (Debian libjs-mathjax)")
endif()
file(REMOVE_RECURSE ${WORK_DIR}/html/_static/mathjax)
file(COPY ${mathjax}/ DESTINATION ${WORK_DIR}/html/_static/mathjax FOLLOW_SYMLINK_CHAIN
  PATTERN unpacked EXCLUDE PATTERN test EXCLUDE)
message(STATUS "documentation site: ${WORK_DIR}/html/index.html (${count} commands' help)")
