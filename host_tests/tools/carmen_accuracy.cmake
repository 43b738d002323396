# cmake -P script: real-data accuracy on a CARMEN log excerpt, end to end.
# lmsego import-carmen LOG (with its odometry), lmsego replay (with the
# odometry as prior when PRIOR is ON), then pairs_error.py against the
# reference pairs TRUTH (written by ../shared/tools/relpose_eval.py
# --write-baseline reference) with the failure rule of the real-data
# figures (0.10 m, 2 deg) and the bounds in BOUNDS (a ;-list of its --max-*
# options). Fails when a step fails or a bound is exceeded.
foreach(var LMSEGO PYTHON SCRIPT LOG TRUTH WORK BOUNDS PRIOR)
    if(NOT DEFINED ${var})
        message(FATAL_ERROR "carmen_accuracy.cmake: ${var} is not set")
    endif()
endforeach()
file(MAKE_DIRECTORY ${WORK})
execute_process(COMMAND ${LMSEGO} import-carmen ${LOG} -o ${WORK}/scans.lms
                        --odometry ${WORK}/odometry.pairs
    ERROR_VARIABLE err RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
    message(FATAL_ERROR "lmsego import-carmen failed (${rc}): ${err}")
endif()
message("${err}")
set(prior_args)
if(PRIOR)
    set(prior_args --prior ${WORK}/odometry.pairs)
endif()
# The excerpts are keyframes about 3 s apart (intel 2.92 s, aces 3.0 s on
# average): replayed at a period no longer than that (issue 15), not at
# the scanner's 13 ms, which would claim a prediction good to centimetres
# and leave a keyframe pair a sensor-rate budget; within the default
# budget of that period (2.9 s: 103 M units a scan).
execute_process(COMMAND ${LMSEGO} replay --period 2.9 ${prior_args} ${WORK}/scans.lms
    OUTPUT_FILE ${WORK}/replay.csv ERROR_VARIABLE err RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
    message(FATAL_ERROR "lmsego replay failed (${rc}): ${err}")
endif()
message("${err}")
execute_process(COMMAND ${PYTHON} ${SCRIPT} ${TRUTH} ${WORK}/replay.csv
                        --fail-m 0.10 --fail-deg 2.0 ${BOUNDS}
    RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
    message(FATAL_ERROR "accuracy bounds exceeded")
endif()
