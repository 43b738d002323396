# cmake -P script: `lmsego replay --budget default` of the adversarial recording
# -> CSV, then adversarial_check.py on it. Fails when the replay fails or a
# line breaks the check.
foreach(var LMSEGO PYTHON SCRIPT STREAM OUT)
    if(NOT DEFINED ${var})
        message(FATAL_ERROR "adversarial_replay.cmake: ${var} is not set")
    endif()
endforeach()
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
