# run_cli.cmake - runs one command and checks its exit code, stdout and
# stderr. Portable `cmake -P` script (no shell), used by the lmsego ctest
# tests.
#
#   cmake -DEXE=prog [-DARG1=.. -DARG2=.. ... -DARG9=..] [-DSTDIN_FILE=f]
#         [-DEXPECT_RC=n|nonzero]           (default 0)
#         [-DEXPECT_STDOUT_FILE=f]          stdout must equal f byte for byte
#         [-DEXPECT_STDOUT_EMPTY=ON]
#         [-DSTDOUT_REGEX=re]               stdout must match re
#         [-DEXPECT_STDERR_EMPTY=ON]
#         [-DSTDERR_ONE_LINE=ON]            stderr is one line "lmsego: ...\n"
#         [-DSTDERR_REGEX=re]
#         -P run_cli.cmake
#
# Arguments are passed one per variable so that no list escaping is needed.
cmake_minimum_required(VERSION 3.21)
if(NOT DEFINED EXE)
    message(FATAL_ERROR "run_cli.cmake: EXE is not set")
endif()

set(args "")
foreach(i RANGE 1 9)
    if(DEFINED ARG${i})
        list(APPEND args "${ARG${i}}")
    endif()
endforeach()

if(DEFINED STDIN_FILE)
    execute_process(COMMAND ${EXE} ${args}
        INPUT_FILE ${STDIN_FILE}
        RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
else()
    execute_process(COMMAND ${EXE} ${args}
        RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
endif()

set(failures "")
macro(fail text)
    string(APPEND failures "  ${text}\n")
endmacro()

if(NOT DEFINED EXPECT_RC)
    set(EXPECT_RC 0)
endif()
if(EXPECT_RC STREQUAL "nonzero")
    if(rc STREQUAL "0" OR NOT rc MATCHES "^[0-9]+$")
        fail("exit code: expected nonzero, got '${rc}'")
    endif()
elseif(NOT rc STREQUAL "${EXPECT_RC}")
    fail("exit code: expected ${EXPECT_RC}, got '${rc}'")
endif()

if(DEFINED EXPECT_STDOUT_FILE)
    file(READ ${EXPECT_STDOUT_FILE} expected)
    if(NOT out STREQUAL expected)
        # Point at the first line that differs.
        string(REPLACE "\n" ";" out_lines "${out}")
        string(REPLACE "\n" ";" exp_lines "${expected}")
        list(LENGTH out_lines n_out)
        list(LENGTH exp_lines n_exp)
        set(where "lengths differ (${n_out} vs ${n_exp} lines)")
        set(n ${n_out})
        if(n_exp LESS n)
            set(n ${n_exp})
        endif()
        if(n GREATER 0)
            math(EXPR last "${n} - 1")
            foreach(i RANGE 0 ${last})
                list(GET out_lines ${i} a)
                list(GET exp_lines ${i} b)
                if(NOT a STREQUAL b)
                    math(EXPR line "${i} + 1")
                    string(SUBSTRING "${a}" 0 200 a)
                    string(SUBSTRING "${b}" 0 200 b)
                    set(where "line ${line}:\n    got:      ${a}\n    expected: ${b}")
                    break()
                endif()
            endforeach()
        endif()
        fail("stdout differs from ${EXPECT_STDOUT_FILE}: ${where}")
    endif()
endif()

if(EXPECT_STDOUT_EMPTY AND NOT out STREQUAL "")
    fail("stdout should be empty, got: ${out}")
endif()
if(DEFINED STDOUT_REGEX AND NOT out MATCHES "${STDOUT_REGEX}")
    fail("stdout does not match '${STDOUT_REGEX}': ${out}")
endif()

if(EXPECT_STDERR_EMPTY AND NOT err STREQUAL "")
    fail("stderr should be empty, got: ${err}")
endif()
if(STDERR_ONE_LINE AND NOT err MATCHES "^lmsego: [^\n]+\n$")
    fail("stderr should be one line starting 'lmsego: ', got: '${err}'")
endif()
if(DEFINED STDERR_REGEX AND NOT err MATCHES "${STDERR_REGEX}")
    fail("stderr does not match '${STDERR_REGEX}': ${err}")
endif()

if(NOT failures STREQUAL "")
    string(REPLACE ";" " " shown "${args}")
    message(FATAL_ERROR "${EXE} ${shown}\n${failures}")
endif()
