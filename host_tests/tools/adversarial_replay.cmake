# cmake -P script: `lmsego replay --budget default` of the adversarial recording
# -> CSV, then adversarial_check.py on it. Fails when the replay fails or a
# line breaks the check.
#
# With -DCASE=<name> (issue 18: one hard case alone, `lmsgen --case`): the
# stream is replayed as cast (--sweep instant, as the target replays it)
# twice, within the live core's budget (--budget default) and unbounded
# (--budget none), into OUT_default.csv and OUT_none.csv, and each is checked
# with `adversarial_check.py --case CASE --budget default|none`.
foreach(var LMSEGO PYTHON SCRIPT STREAM OUT)
    if(NOT DEFINED ${var})
        message(FATAL_ERROR "adversarial_replay.cmake: ${var} is not set")
    endif()
endforeach()
if(NOT DEFINED CASE)
    execute_process(COMMAND ${LMSEGO} replay --budget default ${STREAM}
        OUTPUT_FILE ${OUT} ERROR_VARIABLE err RESULT_VARIABLE rc)
    if(NOT rc EQUAL 0)
        message(FATAL_ERROR "lmsego replay failed (${rc}): ${err}")
    endif()
    message("${err}")
    execute_process(COMMAND ${PYTHON} ${SCRIPT} ${OUT} RESULT_VARIABLE rc)
    if(NOT rc EQUAL 0)
        message(FATAL_ERROR "adversarial scans: a line breaks the check")
    endif()
    return()
endif()
set(failed "")
foreach(budget default none)
    execute_process(COMMAND ${LMSEGO} replay --sweep instant --budget ${budget} ${STREAM}
        OUTPUT_FILE ${OUT}_${budget}.csv ERROR_VARIABLE err RESULT_VARIABLE rc)
    if(NOT rc EQUAL 0)
        message(FATAL_ERROR "lmsego replay --budget ${budget} failed (${rc}): ${err}")
    endif()
    message("--budget ${budget}: ${err}")
    execute_process(COMMAND ${PYTHON} ${SCRIPT} --case ${CASE} --budget ${budget}
        ${OUT}_${budget}.csv RESULT_VARIABLE rc)
    if(NOT rc EQUAL 0)
        string(APPEND failed " --budget ${budget}")
    endif()
endforeach()
if(NOT failed STREQUAL "")
    message(FATAL_ERROR "adversarial case ${CASE}: a line breaks its defined behaviour"
        " (${failed} ): see the lines above")
endif()
