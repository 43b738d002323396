# cmake -P script: one deterministic fuzz run of FUZZER (NAME), RUNS inputs
# of at most MAX_LEN bytes, -seed=1. libFuzzer writes the inputs it finds
# into its first corpus directory, so that is a fresh one in the build tree;
# the committed seed corpus SEEDS is read only. The target's own stdout and
# stderr are closed (-close_fd_mask=3: the CLI commands print; libFuzzer's
# and the sanitizers' reports still come through). Then every committed
# finding of this target (FINDINGS/NAME-*: inputs that once crashed it, see
# README.md) is run once and must pass.
file(REMOVE_RECURSE ${WORK})
file(MAKE_DIRECTORY ${WORK})
execute_process(COMMAND ${FUZZER} -seed=1 -runs=${RUNS} -max_len=${MAX_LEN} -close_fd_mask=3
        ${WORK} ${SEEDS}
    RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
    message(FATAL_ERROR "${NAME} failed (exit ${rc}); the crashing input is in the working directory")
endif()
file(GLOB findings ${FINDINGS}/${NAME}-*)
if(findings)
    execute_process(COMMAND ${FUZZER} ${findings} RESULT_VARIABLE rc)
    if(NOT rc EQUAL 0)
        message(FATAL_ERROR "${NAME}: a committed finding fails again (exit ${rc})")
    endif()
endif()
