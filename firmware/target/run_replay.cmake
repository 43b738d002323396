# run_replay.cmake: runs a replay image under the emulator and checks it.
#   -DEMULATOR=<qemu command, a list ending in -kernel> -DIMAGE=<elf>
#   -DSTREAM=<.lms> -DHOST_LMSEGO=<host lmsego or empty> -DOUT=<prefix>
#   [-DMAX_INSNS=<gate on the largest scan's instructions>]
#   [-DHOST_ARGS=<options of the host's lmsego replay, e.g. --budget;default>]
# Passes when the image exits 0, prints its '# insns_per_scan' line (with
# a max at or below MAX_INSNS, when given: instruction counts under
# -icount are the same run after run, so the gate catches any growth; and
# at or below the budget it prints, when it prints one), and
# (with HOST_LMSEGO) every other line equals the host's `lmsego replay`.
# Writes OUT.target (all output), OUT.host, OUT.figures (the '#' lines).
include(${CMAKE_CURRENT_LIST_DIR}/run_image.cmake)
lmsego_run_image("${EMULATOR}" "${IMAGE}" "${OUT}" 1400)
if(NOT image_rc EQUAL 0)
    message(FATAL_ERROR "the image exited with '${image_rc}' (faults: 121-127, see target.h): ${image_err}")
endif()
if(NOT figures MATCHES "# insns_per_scan median=([0-9]+) max=([0-9]+)")
    message(FATAL_ERROR "no '# insns_per_scan' line")
endif()
if(MAX_INSNS)
    if(CMAKE_MATCH_2 GREATER MAX_INSNS)
        message(FATAL_ERROR "the hardest scan took ${CMAKE_MATCH_2} instructions, above the "
            "gate of ${MAX_INSNS} (firmware/target/insns_gates.cmake): the estimator grew "
            "slower; find why, or move the gate with the new figures in docs/firmware.md")
    endif()
    message(STATUS "hardest scan ${CMAKE_MATCH_2} instructions, gate ${MAX_INSNS}")
endif()
if(figures MATCHES "max=([0-9]+) budget=([0-9]+)")
    if(CMAKE_MATCH_1 GREATER CMAKE_MATCH_2)
        message(FATAL_ERROR "the hardest scan took ${CMAKE_MATCH_1} instructions, above its "
            "budget of ${CMAKE_MATCH_2}: a work cost in estimator/ego_work.h is too low")
    endif()
    message(STATUS "hardest scan ${CMAKE_MATCH_1} instructions, budget ${CMAKE_MATCH_2}")
endif()
lmsego_check_stack("${figures}")
if(HOST_LMSEGO STREQUAL "")
    message(STATUS "no LMSEGO_HOST_LMSEGO: output not compared with the host")
    return()
endif()
execute_process(COMMAND "${HOST_LMSEGO}" replay ${HOST_ARGS} "${STREAM}"
    OUTPUT_FILE "${OUT}.host" ERROR_QUIET RESULT_VARIABLE hrc)
if(NOT hrc EQUAL 0)
    message(FATAL_ERROR "host lmsego replay failed: ${hrc}")
endif()
# The target's output without its '#' lines, byte for byte.
lmsego_csv_text("${OUT}.target" target_text)
file(READ "${OUT}.host" host_text)
if(NOT target_text STREQUAL host_text)
    file(WRITE "${OUT}.target-csv" "${target_text}")
    message(FATAL_ERROR "target output differs from the host's: diff ${OUT}.host ${OUT}.target-csv")
endif()
string(LENGTH "${host_text}" n)
message(STATUS "identical to the host (${n} bytes)")
