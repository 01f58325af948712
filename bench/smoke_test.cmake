# ctest bench_smoke: the driver on the N = 2 knife-edge chain, generated code against the
# hand-written limit. Checks that it runs and that both integrate to the same state; no timing.
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
