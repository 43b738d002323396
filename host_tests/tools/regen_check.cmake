# regen_check.cmake - regenerates a shipped recording with lmsgen and
# checks that the stream, the truth (`lmsego scans` output) and the
# expected `lmsego stats` line are byte-identical to the shipped files.
#
#   cmake -DLMSGEN=path -DNAME=room_181_mm -DSHIPPED_DIR=dir -DOUT_DIR=dir
#         -DARG1=.. -DARG2=.. ... (lmsgen options, one per variable)
#         -P regen_check.cmake
cmake_minimum_required(VERSION 3.21)
foreach(var LMSGEN NAME SHIPPED_DIR OUT_DIR)
    if(NOT DEFINED ${var})
        message(FATAL_ERROR "regen_check.cmake: ${var} is not set")
    endif()
endforeach()

set(args "")
foreach(i RANGE 1 20)
    if(DEFINED ARG${i})
        list(APPEND args "${ARG${i}}")
    endif()
endforeach()

file(MAKE_DIRECTORY ${OUT_DIR})
set(out ${OUT_DIR}/${NAME})
execute_process(
    COMMAND ${LMSGEN} ${args} -o ${out}.lms --truth ${out}.scans --expect-stats ${out}.stats
    RESULT_VARIABLE rc ERROR_VARIABLE err)
if(NOT rc STREQUAL "0")
    message(FATAL_ERROR "lmsgen failed (${rc}): ${err}")
endif()

set(failed "")
foreach(ext lms scans stats)
    execute_process(
        COMMAND ${CMAKE_COMMAND} -E compare_files ${out}.${ext} ${SHIPPED_DIR}/${NAME}.${ext}
        RESULT_VARIABLE same)
    if(NOT same STREQUAL "0")
        string(APPEND failed " ${NAME}.${ext}")
    endif()
endforeach()
if(NOT failed STREQUAL "")
    message(FATAL_ERROR "regenerated files differ from the shipped ones:${failed}\n"
        "(regenerated into ${OUT_DIR})")
endif()
