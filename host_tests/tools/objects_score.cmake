# cmake -P script: lmsego replay --sweep instant --objects OUT STREAM, the
# objects file's header checked against the documented columns, then
# objects_score.py TRUTH OUT --from FROM with the bounds in BOUNDS (a
# ;-list of its --min/--max options). Fails when the replay fails, the
# header differs or a bound is missed. With -DMOVING=ON: the firmware
# loop's compact objects instead (replay --moving: its "o," lines, each
# with the loop's eleven motion columns' count checked, go to OUT under
# the same header).
foreach(var LMSEGO PYTHON SCRIPT STREAM TRUTH OUT BOUNDS FROM)
    if(NOT DEFINED ${var})
        message(FATAL_ERROR "objects_score.cmake: ${var} is not set")
    endif()
endforeach()
if(MOVING)
    execute_process(COMMAND ${LMSEGO} replay --sweep instant ${EXTRA} --moving ${STREAM}
        OUTPUT_FILE ${OUT}.motion ERROR_VARIABLE err RESULT_VARIABLE rc)
    if(NOT rc EQUAL 0)
        message(FATAL_ERROR "lmsego replay --moving failed (${rc}): ${err}")
    endif()
    file(STRINGS ${OUT}.motion all)
    set(objects "scan,id,cx_m,cy_m,length_m,width_m,vx_mps,vy_mps,points\n")
    foreach(line IN LISTS all)
        if(line MATCHES "^o,")
            string(REPLACE "," ";" fields "${line}")
            list(LENGTH fields n)
            if(NOT n EQUAL 10)
                message(FATAL_ERROR "an objects line without its ten fields: '${line}'")
            endif()
            string(SUBSTRING "${line}" 2 -1 rest)
            string(APPEND objects "${rest}\n")
        endif()
    endforeach()
    file(WRITE ${OUT} "${objects}")
else()
    execute_process(COMMAND ${LMSEGO} replay --sweep instant ${EXTRA} --objects ${OUT} ${STREAM}
        OUTPUT_FILE ${OUT}.motion ERROR_VARIABLE err RESULT_VARIABLE rc)
    if(NOT rc EQUAL 0)
        message(FATAL_ERROR "lmsego replay --objects failed (${rc}): ${err}")
    endif()
endif()
file(STRINGS ${OUT} lines)
list(GET lines 0 header)
if(NOT header STREQUAL "scan,id,cx_m,cy_m,length_m,width_m,vx_mps,vy_mps,points")
    message(FATAL_ERROR "unexpected header in ${OUT}: '${header}'")
endif()
list(LENGTH lines count)
if(count LESS 2)
    message(FATAL_ERROR "no object in ${OUT}")
endif()
execute_process(COMMAND ${PYTHON} ${SCRIPT} ${TRUTH} ${OUT} --from ${FROM} ${BOUNDS}
    RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
    message(FATAL_ERROR "moving-object bounds missed")
endif()
