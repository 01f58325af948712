# python:mypy — Debian's mypy accepts python/typecheck/user_script.py (--strict) against the built
# package (its annotations, nhc/_nhc.pyi, py.typed), and rejects user_script_wrong.py with its two
# errors at their lines, and no others. Both runs take the same options (--strict), so the second
# reads what the first wrote to the cache (NumPy's and the package's types) instead of analysing
# them again: a cache written under other options is discarded whole.
# usage: cmake -DPYTHON= -DPYTHON_DIR= -DSOURCE_DIR= -DWORK_DIR= -P check.cmake
cmake_minimum_required(VERSION 3.20)
file(REMOVE_RECURSE ${WORK_DIR})
file(MAKE_DIRECTORY ${WORK_DIR})
set(dir ${SOURCE_DIR}/python/typecheck)
execute_process(COMMAND ${CMAKE_COMMAND} -E env MYPYPATH=${PYTHON_DIR}
                        ${PYTHON} -m mypy --strict --config-file ${dir}/mypy.ini --cache-dir ${WORK_DIR}/cache ${dir}/user_script.py
  WORKING_DIRECTORY ${WORK_DIR} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "mypy rejected user_script.py (${rc}):\n${out}${err}")
endif()
message(STATUS "user_script.py: ${out}")
execute_process(COMMAND ${CMAKE_COMMAND} -E env MYPYPATH=${PYTHON_DIR}
                        ${PYTHON} -m mypy --strict --config-file ${dir}/mypy.ini --cache-dir ${WORK_DIR}/cache ${dir}/user_script_wrong.py
  WORKING_DIRECTORY ${WORK_DIR} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(rc EQUAL 0 OR NOT out MATCHES "user_script_wrong.py:5: error: Argument \"t_end\"" OR
   NOT out MATCHES "user_script_wrong.py:6: error: Incompatible types in assignment" OR
   NOT out MATCHES "Found 2 errors in 1 file")
  message(FATAL_ERROR "mypy did not report the two errors of user_script_wrong.py (${rc}):\n${out}${err}")
endif()
message(STATUS "user_script_wrong.py: ${out}")
