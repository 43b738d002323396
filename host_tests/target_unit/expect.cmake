# expect.cmake: a command must end with an expected status and/or print a
# text.  -DCMD=<list> [-DRC=<code> | -DNONZERO=ON] [-DTEXT=<regex in stdout+stderr>]
execute_process(COMMAND ${CMD} OUTPUT_VARIABLE out ERROR_VARIABLE err RESULT_VARIABLE rc
    TIMEOUT 300)
if(DEFINED RC AND NOT rc STREQUAL "${RC}")
    message(FATAL_ERROR "exit status '${rc}', expected ${RC}\n${out}${err}")
endif()
if(NONZERO AND rc EQUAL 0)
    message(FATAL_ERROR "the command succeeded; it should have failed\n${out}${err}")
endif()
if(DEFINED TEXT AND NOT "${out}${err}" MATCHES "${TEXT}")
    message(FATAL_ERROR "output does not match '${TEXT}':\n${out}${err}")
endif()
