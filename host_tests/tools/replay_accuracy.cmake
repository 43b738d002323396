# cmake -P script: lmsego replay STREAM (with EXTRA options) -> CSV, then
# SCRIPT (pairs_error.py, or nees.py with SCRIPT_ARGS empty) against TRUTH
# with the bounds in BOUNDS (a ;-list of its --max-* options). Fails when
# the replay fails or a bound is exceeded. PRIOR_SCALE: see below.
foreach(var LMSEGO PYTHON SCRIPT STREAM TRUTH OUT BOUNDS)
    if(NOT DEFINED ${var})
        message(FATAL_ERROR "replay_accuracy.cmake: ${var} is not set")
    endif()
endforeach()
# PRIOR_SCALE (optional): an odometry prior, the truth's translations times
# it (scaled_prior.py, SCALED_PRIOR), given with --prior.
if(PRIOR_SCALE)
    execute_process(COMMAND ${PYTHON} ${SCALED_PRIOR} ${TRUTH} ${PRIOR_SCALE} ${OUT}.prior
        RESULT_VARIABLE rc)
    if(NOT rc EQUAL 0)
        message(FATAL_ERROR "scaled_prior.py failed (${rc})")
    endif()
    list(APPEND EXTRA --prior ${OUT}.prior)
endif()
execute_process(COMMAND ${LMSEGO} replay ${EXTRA} ${STREAM}
    OUTPUT_FILE ${OUT} ERROR_VARIABLE err RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
    message(FATAL_ERROR "lmsego replay failed (${rc}): ${err}")
endif()
message("${err}")
if(NOT DEFINED SCRIPT_ARGS)
    set(SCRIPT_ARGS --exclude-flags 2) # pairs_error.py: aperture lines' length is not measured
endif()
execute_process(COMMAND ${PYTHON} ${SCRIPT} ${TRUTH} ${OUT} ${SCRIPT_ARGS} ${BOUNDS}
    RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
    message(FATAL_ERROR "accuracy bounds exceeded")
endif()
