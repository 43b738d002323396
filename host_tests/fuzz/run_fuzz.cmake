# cmake -P script: one deterministic fuzz run. libFuzzer writes the inputs it
# finds into its first corpus directory, so that is a fresh one in the build
# tree; the committed seed corpus is read only.
file(REMOVE_RECURSE ${WORK})
file(MAKE_DIRECTORY ${WORK})
execute_process(COMMAND ${FUZZER} -seed=1 -runs=${RUNS} -max_len=2048 ${WORK} ${SEEDS}
    RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
    message(FATAL_ERROR "fuzz_codec failed (exit ${rc}); the crashing input is in the working directory")
endif()
