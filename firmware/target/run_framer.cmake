# run_framer.cmake: runs a framer image (main_framer.c) under the emulator
# and checks it.
#   -DEMULATOR=<qemu command, a list ending in -kernel> -DIMAGE=<elf>
#   -DSTREAM=<.lms> -DHOST_LMSEGO=<host lmsego or empty> -DOUT=<prefix>
#   -DMAX_FRAMER=<insns per byte> -DMAX_TOTAL=<insns per byte> (two decimals)
# Passes when the image exits 0; its counts equal the host's `lmsego stats
# STREAM` (bytes, telegrams, scans, CRC, length and decode errors; without
# HOST_LMSEGO: scans > 0 and no CRC error); and framer_insns_per_byte and
# framer_decoder_insns_per_byte are at most MAX_FRAMER and MAX_TOTAL
# (instruction counts under -icount are the same run after run: a gate
# above the measured figure catches silent growth). Writes OUT.target (all
# output) and OUT.figures (the '#' lines).
include(${CMAKE_CURRENT_LIST_DIR}/run_image.cmake)
lmsego_run_image("${EMULATOR}" "${IMAGE}" "${OUT}" 600)
if(NOT image_rc EQUAL 0)
    message(FATAL_ERROR "the image exited with '${image_rc}' "
        "(1: the passes disagree; faults: 121-127, see target.h): ${image_err}")
endif()

# The image's counts, as `lmsego stats` names them.
set(count_names bytes telegrams scans crc_errors length_errors decode_errors)
if(NOT figures MATCHES "# framer( [^;]*)")
    message(FATAL_ERROR "no '# framer' line")
endif()
set(counts "${CMAKE_MATCH_1}")
foreach(name IN LISTS count_names)
    if(NOT counts MATCHES " ${name}=([0-9]+)")
        message(FATAL_ERROR "no '${name}=' in the '# framer' line")
    endif()
    set(target_${name} ${CMAKE_MATCH_1})
endforeach()
if(HOST_LMSEGO STREQUAL "")
    message(STATUS "no LMSEGO_HOST_LMSEGO: counts not compared with the host")
    if(target_scans EQUAL 0 OR NOT target_crc_errors EQUAL 0)
        message(FATAL_ERROR "scans=${target_scans} crc_errors=${target_crc_errors}: "
            "expected scans and no CRC error")
    endif()
else()
    execute_process(COMMAND "${HOST_LMSEGO}" stats "${STREAM}"
        OUTPUT_VARIABLE host ERROR_QUIET RESULT_VARIABLE hrc)
    if(NOT hrc EQUAL 0)
        message(FATAL_ERROR "host lmsego stats failed: ${hrc}")
    endif()
    foreach(name IN LISTS count_names)
        if(NOT host MATCHES "(^| )${name}=([0-9]+)")
            message(FATAL_ERROR "no '${name}=' in the host's stats: ${host}")
        endif()
        if(NOT CMAKE_MATCH_2 EQUAL target_${name})
            message(FATAL_ERROR "${name}: target ${target_${name}}, host ${CMAKE_MATCH_2}")
        endif()
    endforeach()
    message(STATUS "counts equal the host's: ${host}")
endif()

# Figures with two decimals, compared in hundredths.
function(gate name limit)
    if(NOT figures MATCHES "# ${name}=([0-9]+)\\.([0-9][0-9])")
        message(FATAL_ERROR "no '# ${name}=' line")
    endif()
    set(shown "${CMAKE_MATCH_1}.${CMAKE_MATCH_2}")
    set(value "${CMAKE_MATCH_1}${CMAKE_MATCH_2}")
    if(NOT limit MATCHES "^([0-9]+)\\.([0-9][0-9])$")
        message(FATAL_ERROR "the limit of ${name} must have two decimals: '${limit}'")
    endif()
    if(value GREATER "${CMAKE_MATCH_1}${CMAKE_MATCH_2}")
        message(FATAL_ERROR "${name}=${shown}: above its gate ${limit} "
            "(firmware/target/measure.cmake)")
    endif()
    message(STATUS "${name}=${shown}: within its gate ${limit}")
endfunction()
gate(framer_insns_per_byte "${MAX_FRAMER}")
gate(framer_decoder_insns_per_byte "${MAX_TOTAL}")
