# measure.cmake: two budgets of issue 6 measured on the target (included
# from CMakeLists.txt after every replay image is defined; docs/firmware.md).
#
# 1. Worst-case stack through the call graph. lmsego_stack_check(IMAGE) runs
#    stack_graph.py on the image (the .ci call graphs gcc writes with
#    -fcallgraph-info=su, the image's map and disassembly, the indirect
#    calls of stack_indirect.txt) after every build of IMAGE, reporting
#    build/<preset>/stack_IMAGE.txt, and adds the ctest test
#    target_stack_IMAGE (label "target"), which fails above 4 KiB or on
#    anything the analysis cannot bound (recursion, a VLA, an undeclared
#    indirect call). target_stack_graph_selftest shows the checker failing
#    on hand-written graphs that should fail (host_tests/target_unit/stack_fixtures).
#
# 2. The framer and the B0 decoder in instructions per input byte: the
#    images framer_<stream> (main_framer.c) and the ctest tests
#    target_framer_<stream> (label "target", run_framer.cmake).

find_package(Python3 COMPONENTS Interpreter)
find_program(LMSEGO_ARM_OBJDUMP arm-none-eabi-objdump)
set(LMSEGO_STACK_LIMIT 4096)
# The hardware exception frame: 8 words, 26 with the FPU context (M4F).
if(LMSEGO_CPU STREQUAL "cortex-m4f")
    set(LMSEGO_EXCEPTION_FRAME 104)
else()
    set(LMSEGO_EXCEPTION_FRAME 32)
endif()
if(NOT CMAKE_C_FLAGS MATCHES "-fcallgraph-info=su")
    message(WARNING "CMAKE_C_FLAGS lack -fcallgraph-info=su (a build directory configured "
        "before cmake/arm-none-eabi.cmake had it?): the worst-case stack cannot be computed; "
        "configure a fresh build directory")
endif()

function(lmsego_stack_check image)
    if(NOT Python3_Interpreter_FOUND OR NOT LMSEGO_ARM_OBJDUMP)
        message(STATUS "No python3 or arm-none-eabi-objdump: "
            "worst-case stack of ${image} not computed")
        return()
    endif()
    get_target_property(link_dir ${image} BINARY_DIR)
    set(args ${Python3_EXECUTABLE} ${CMAKE_CURRENT_FUNCTION_LIST_DIR}/stack_graph.py
        --image $<TARGET_FILE:${image}> --map ${CMAKE_BINARY_DIR}/bin/${image}.map
        --build-dir ${CMAKE_BINARY_DIR} --link-dir ${link_dir}
        --objdump ${LMSEGO_ARM_OBJDUMP}
        --indirect ${CMAKE_CURRENT_FUNCTION_LIST_DIR}/stack_indirect.txt
        --exception-frame ${LMSEGO_EXCEPTION_FRAME} --limit ${LMSEGO_STACK_LIMIT}
        --out ${CMAKE_BINARY_DIR}/stack_${image}.txt)
    # After every link: the figure, never a failed build (ctest checks).
    add_custom_command(TARGET ${image} POST_BUILD COMMAND ${args} --report-only VERBATIM)
    add_test(NAME target_stack_${image} COMMAND ${args} --check)
    set_tests_properties(target_stack_${image} PROPERTIES LABELS "target")
endfunction()

lmsego_stack_check(replay_campus_181_cm)

# The checker must fail on what it cannot bound: a recursion, an indirect
# call nobody declared, a VLA; and give the right sum on a small graph.
if(Python3_Interpreter_FOUND)
    add_test(NAME target_stack_graph_selftest
        COMMAND ${CMAKE_COMMAND} -DPYTHON=${Python3_EXECUTABLE}
            -DSCRIPT=${CMAKE_CURRENT_LIST_DIR}/stack_graph.py
            -DFIXTURES=${PROJECT_SOURCE_DIR}/host_tests/target_unit/stack_fixtures
            -DOUT_DIR=${CMAKE_BINARY_DIR}/target_out
            -P ${PROJECT_SOURCE_DIR}/host_tests/target_unit/stack_fixtures/selftest.cmake)
    set_tests_properties(target_stack_graph_selftest PROPERTIES LABELS "target")
endif()

# Framer and decoder per input byte, on a 181-value and a 361-value stream.
# Gates (framer, framer + decoder, instructions per byte): the larger of
# the Cortex-M3 and M4F figures of the build's optimisation (they differ
# by less than 0.4 %), plus 3 %. Instruction counts under -icount repeat
# exactly, so only a change of the code or the compiler moves them: raise a
# gate when a change is meant to cost more, and say why.
#                                       measured (M3, -Os / -O2)
if(CMAKE_BUILD_TYPE STREQUAL "Release") # -O2
    set(LMSEGO_FRAMER_GATE_campus_181_cm 15.00 31.80) # 14.55 30.85
    set(LMSEGO_FRAMER_GATE_fast_361_cm 14.30 30.40)   # 13.84 29.50
else()                                  # -Os
    set(LMSEGO_FRAMER_GATE_campus_181_cm 15.15 37.60) # 14.69 36.48
    set(LMSEGO_FRAMER_GATE_fast_361_cm 14.35 36.15)   # 13.91 35.07
endif()
foreach(name campus_181_cm fast_361_cm)
    set(image framer_${name})
    lmsego_target_image(${image} ${CMAKE_CURRENT_LIST_DIR}/main_framer.c
        ${CMAKE_CURRENT_LIST_DIR}/report.c $<TARGET_OBJECTS:stream_${name}>)
    # The driver's framer and decoder; ego_format_fixed for the figures.
    target_link_libraries(${image} PRIVATE ego_firmware)
    list(GET LMSEGO_FRAMER_GATE_${name} 0 max_framer)
    list(GET LMSEGO_FRAMER_GATE_${name} 1 max_total)
    add_test(NAME target_${image}
        COMMAND ${CMAKE_COMMAND}
            "-DEMULATOR=${CMAKE_CROSSCOMPILING_EMULATOR}"
            -DIMAGE=$<TARGET_FILE:${image}>
            -DSTREAM=${PROJECT_SOURCE_DIR}/host_tests/data/sequences/${name}.lms
            -DHOST_LMSEGO=${LMSEGO_HOST_LMSEGO}
            -DOUT=${CMAKE_BINARY_DIR}/target_out/${image}
            -DMAX_FRAMER=${max_framer} -DMAX_TOTAL=${max_total}
            -P ${CMAKE_CURRENT_LIST_DIR}/run_framer.cmake)
    set_tests_properties(target_${image} PROPERTIES LABELS "target" TIMEOUT 600)
endforeach()
