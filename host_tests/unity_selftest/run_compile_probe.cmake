# run_compile_probe.cmake - compiles a compile-time probe of the harness
# once per case and checks which cases the compiler rejects.
#
#   cmake -DCC=<C compiler> -DHARNESS=<dir with unity.h> -DSOURCE=<probe .c>
#         -DEXPECTED=<cases file> -DFLAGS="<warning flags, space-separated>"
#         -P run_compile_probe.cmake
#
# EXPECTED has one case per line, "<CASE> <fails|builds> <regex>..."
# (# starts a comment). Each case is compiled with -fsyntax-only (fast,
# nothing written), FLAGS and -DPROBE_<CASE>. A "builds" case must compile
# without a diagnostic; a "fails" case must be rejected, and the compiler's
# output, with SOURCE replaced by @PROBE_SOURCE@, must match every regex.
# The "builds" cases show that a rejection comes from the argument the
# probe varies, not from anything else in it.
foreach(var CC HARNESS SOURCE EXPECTED FLAGS)
    if(NOT DEFINED ${var})
        message(FATAL_ERROR "run_compile_probe.cmake: -D${var}=... is required")
    endif()
endforeach()

separate_arguments(flags UNIX_COMMAND "${FLAGS}")
file(STRINGS "${EXPECTED}" lines)
set(problems "")
set(count 0)
foreach(line IN LISTS lines)
    string(STRIP "${line}" line)
    if(line STREQUAL "" OR line MATCHES "^#")
        continue()
    endif()
    string(REGEX REPLACE "[ \t]+" ";" fields "${line}")
    list(POP_FRONT fields case outcome)
    if(NOT outcome MATCHES "^(fails|builds)$")
        message(FATAL_ERROR "${EXPECTED}: '${line}': the outcome must be fails or builds")
    endif()
    math(EXPR count "${count} + 1")

    execute_process(
        COMMAND "${CC}" -std=c11 -fsyntax-only ${flags} -I "${HARNESS}" -DPROBE_${case} "${SOURCE}"
        OUTPUT_VARIABLE out
        ERROR_VARIABLE out
        RESULT_VARIABLE status)
    string(REPLACE "${SOURCE}" "@PROBE_SOURCE@" out "${out}")

    if(outcome STREQUAL "builds")
        if(NOT status EQUAL 0 OR NOT out STREQUAL "")
            string(APPEND problems "${case}: expected to build cleanly, got status ${status}:\n${out}\n")
        endif()
    else()
        if(status EQUAL 0)
            string(APPEND problems "${case}: expected the compiler to reject it, it built:\n${out}\n")
        endif()
        foreach(pattern IN LISTS fields)
            if(NOT out MATCHES "${pattern}")
                string(APPEND problems "${case}: the diagnostics do not match '${pattern}':\n${out}\n")
            endif()
        endforeach()
    endif()
endforeach()

if(count EQUAL 0)
    message(FATAL_ERROR "${EXPECTED}: no cases")
endif()
if(problems)
    message(FATAL_ERROR "${SOURCE}:\n${problems}")
endif()
message(STATUS "${SOURCE}: ${count} cases rejected or accepted as expected")
