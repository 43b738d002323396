# run_replay.cmake: runs a replay image under the emulator and checks it.
#   -DEMULATOR=<qemu command, a list ending in -kernel> -DIMAGE=<elf>
#   -DSTREAM=<.lms> -DHOST_LMSEGO=<host lmsego or empty> -DOUT=<prefix>
#   [-DMAX_INSNS=<gate on the largest scan's instructions>]
# Passes when the image exits 0, prints its '# insns_per_scan' line (with
# a max at or below MAX_INSNS, when given: instruction counts under
# -icount are the same run after run, so the gate catches any growth), and
# (with HOST_LMSEGO) every other line equals the host's `lmsego replay`.
# Writes OUT.target (all output), OUT.host, OUT.figures (the '#' lines).
get_filename_component(dir "${OUT}" DIRECTORY)
file(MAKE_DIRECTORY "${dir}")
execute_process(COMMAND ${EMULATOR} ${IMAGE}
    OUTPUT_FILE "${OUT}.target" ERROR_VARIABLE err RESULT_VARIABLE rc TIMEOUT 1400)
if(NOT rc EQUAL 0)
    message(FATAL_ERROR "the image exited with '${rc}' (faults: 121-127, see target.h): ${err}")
endif()
file(STRINGS "${OUT}.target" figures REGEX "^#")
file(WRITE "${OUT}.figures" "")
foreach(line IN LISTS figures)
    message(STATUS "${line}")
    file(APPEND "${OUT}.figures" "${line}\n")
endforeach()
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
# The stack section is 4 KiB with .bss below it: keep a 512-byte margin.
if(NOT figures MATCHES "# stack_bytes used=([0-9]+)")
    message(FATAL_ERROR "no '# stack_bytes' line")
endif()
if(CMAKE_MATCH_1 GREATER 3584)
    message(FATAL_ERROR "stack high-water mark ${CMAKE_MATCH_1} B: above 3.5 KiB of 4 KiB")
endif()
if(HOST_LMSEGO STREQUAL "")
    message(STATUS "no LMSEGO_HOST_LMSEGO: output not compared with the host")
    return()
endif()
execute_process(COMMAND "${HOST_LMSEGO}" replay "${STREAM}"
    OUTPUT_FILE "${OUT}.host" ERROR_QUIET RESULT_VARIABLE hrc)
if(NOT hrc EQUAL 0)
    message(FATAL_ERROR "host lmsego replay failed: ${hrc}")
endif()
# The target's output without its '#' lines, byte for byte.
file(READ "${OUT}.target" target_text)
string(REGEX REPLACE "(^|\n)#[^\n]*" "" target_text "${target_text}")
string(REGEX REPLACE "^\n" "" target_text "${target_text}")
file(READ "${OUT}.host" host_text)
if(NOT target_text STREQUAL host_text)
    file(WRITE "${OUT}.target-csv" "${target_text}")
    message(FATAL_ERROR "target output differs from the host's: diff ${OUT}.host ${OUT}.target-csv")
endif()
string(LENGTH "${host_text}" n)
message(STATUS "identical to the host (${n} bytes)")
