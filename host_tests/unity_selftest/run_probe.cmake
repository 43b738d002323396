# run_probe.cmake - runs one harness self-test probe and checks it.
#
#   cmake -DPROBE=<exe> -DSOURCE=<probe .c as the compiler saw it>
#         -DEXPECTED=<expected stdout> -DFAILURES=<n> [-DACTUAL=<file>]
#         -P run_probe.cmake
#
# Passes when the probe's stdout, with every occurrence of SOURCE replaced
# by the token @PROBE_SOURCE@ (__FILE__ is absolute under CMake), equals
# EXPECTED byte for byte, its exit status equals FAILURES (UNITY_END()
# returns the failure count) and it wrote nothing to stderr (a sanitizer
# report, or the harness's own "outside RUN_TEST" message, fails the check).
# The normalised output is written to ACTUAL, if given, for diffing.
foreach(var PROBE SOURCE EXPECTED FAILURES)
    if(NOT DEFINED ${var})
        message(FATAL_ERROR "run_probe.cmake: -D${var}=... is required")
    endif()
endforeach()

execute_process(COMMAND "${PROBE}"
    OUTPUT_VARIABLE out
    ERROR_VARIABLE err
    RESULT_VARIABLE status)
string(REPLACE "${SOURCE}" "@PROBE_SOURCE@" out "${out}")
file(READ "${EXPECTED}" expected)
if(DEFINED ACTUAL)
    file(WRITE "${ACTUAL}" "${out}")
endif()

set(problems "")
if(NOT out STREQUAL expected)
    string(APPEND problems "stdout differs from ${EXPECTED}"
        "\n--- expected ---\n${expected}--- actual ---\n${out}--- end ---\n")
endif()
if(NOT status STREQUAL "${FAILURES}")
    string(APPEND problems "exit status '${status}', expected ${FAILURES}\n")
endif()
if(NOT err STREQUAL "")
    string(APPEND problems "unexpected stderr:\n${err}\n")
endif()
if(problems)
    message(FATAL_ERROR "${PROBE}:\n${problems}")
endif()
message(STATUS "${PROBE}: output and exit status ${status} as expected")
