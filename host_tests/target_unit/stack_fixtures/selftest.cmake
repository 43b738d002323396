# selftest.cmake: firmware/target/stack_graph.py on hand-written call graphs
# (gcc's .ci format, -fcallgraph-info=su), ctest target_stack_graph_selftest.
#   -DPYTHON=<python3> -DSCRIPT=<stack_graph.py> -DFIXTURES=<this directory>
#   -DOUT_DIR=<where the results go>
# ok.ci must give its hand-computed sum; recursion.ci, indirect.ci and
# vla.ci must fail, each for its own reason.
file(MAKE_DIRECTORY "${OUT_DIR}")

# expect(NAME RC REGEX [ARGS...]): exit status RC and output matching REGEX.
function(expect name rc_expected regex)
    execute_process(COMMAND ${PYTHON} ${SCRIPT} --ci ${FIXTURES}/${name}.ci
            --indirect ${FIXTURES}/indirect.txt --out ${OUT_DIR}/stack_fixture_${name}.txt ${ARGN}
        OUTPUT_VARIABLE out ERROR_VARIABLE err RESULT_VARIABLE rc)
    if(NOT rc EQUAL rc_expected OR NOT "${out}${err}" MATCHES "${regex}")
        message(FATAL_ERROR "${name}: exit status ${rc} (expected ${rc_expected}), "
            "output not matching '${regex}':\n${out}${err}")
    endif()
    message(STATUS "${name}: as expected: ${out}${err}")
endfunction()

# Reset_Handler 16 + main 24 + c 200 (through the declared pointer) beats
# a 100 + b 8; SysTick_Handler 8 + b 8; one exception frame 32 + 4.
expect(ok 0 "stack_worst=240 path=Reset_Handler>main>c handlers=16 exception_frame=36 total=292 "
    --handler SysTick_Handler --exception-frame 32 --check --limit 292)
expect(ok 1 "total=292 .*worst-case stack 292 B > limit 291 B"
    --handler SysTick_Handler --exception-frame 32 --check --limit 291)
expect(recursion 1 "error: recursion: walk>visit>walk")
expect(indirect 1 "error: dispatch .*makes an indirect call and is not in")
expect(vla 1 "error: fill: dynamic,bounded frame")
