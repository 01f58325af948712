# ctest bench_smoke: the driver on the N = 2 knife-edge chain, generated code against the
# hand-written limit. Checks that it runs and that both integrate to the same state; then the particle
# chain and the front-end harness at tiny N. No timing.
file(REMOVE_RECURSE ${OUT})
execute_process(COMMAND ${PYTHON} ${SOURCE}/knife_chain.py ${OUT} 2 RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "knife_chain.py failed (${rc})")
endif()
execute_process(
  COMMAND ${BENCH} ${OUT}/knife_chain_2.toml --out ${OUT} --quick
          --handwritten ${SOURCE}/knife_chain_handwritten.hpp --define NHC_BENCH_CHAIN_N=2
  RESULT_VARIABLE rc OUTPUT_VARIABLE json ERROR_VARIABLE err)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "nhc_bench failed (${rc}): ${err}")
endif()
message(STATUS "${json}")
string(JSON steps GET "${json}" steps)
string(JSON hw_steps GET "${json}" handwritten_steps)
string(JSON diff GET "${json}" handwritten_final_difference)
string(JSON states GET "${json}" n_states)
if(NOT states EQUAL 14)
  message(FATAL_ERROR "expected 14 states, got ${states}")
endif()
if(steps LESS 10 OR hw_steps LESS 10)
  message(FATAL_ERROR "too few steps: ${steps} generated, ${hw_steps} hand-written")
endif()
# Same equations, same tolerances: the final states agree to well within the tolerance scale.
if(diff GREATER 1e-5)
  message(FATAL_ERROR "generated and hand-written final states differ by ${diff}")
endif()

# The second family: the particle chain (second-order constraints) at N = 2 through the driver.
execute_process(COMMAND ${PYTHON} ${SOURCE}/particle_chain.py ${OUT} 2 RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "particle_chain.py failed (${rc})")
endif()
execute_process(COMMAND ${BENCH} ${OUT}/particle_chain_2.toml --out ${OUT}/particle --quick
  RESULT_VARIABLE rc OUTPUT_VARIABLE json ERROR_VARIABLE err)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "nhc_bench failed on the particle chain (${rc}): ${err}")
endif()
string(JSON states GET "${json}" n_states)
string(JSON steps GET "${json}" steps)
if(NOT states EQUAL 10 OR steps LESS 10)
  message(FATAL_ERROR "particle chain N = 2: expected 10 states and at least 10 steps, got ${states}, ${steps}")
endif()

# The front-end harness (bench/frontend_scaling.py) on N = 1, 2: every command ok, a slope.
execute_process(COMMAND ${PYTHON} ${SOURCE}/frontend_scaling.py ${NHC} ${OUT}/frontend.json --timeout 60 1 2
  RESULT_VARIABLE rc ERROR_VARIABLE err)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "frontend_scaling.py failed (${rc}): ${err}")
endif()
file(READ ${OUT}/frontend.json fe)
foreach(i 0 1)
  string(JSON status GET "${fe}" rows ${i} status)
  if(NOT status STREQUAL "ok")
    message(FATAL_ERROR "frontend_scaling.py row ${i}: ${status}")
  endif()
endforeach()
string(JSON fit GET "${fe}" slope_all)
message(STATUS "front-end slope over N = 1, 2: ${fit}")
