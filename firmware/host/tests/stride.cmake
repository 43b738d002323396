# cmake -P script: stride-2 evaluation on the 12-scan intel excerpt.
#   import-carmen --stride 2 keeps scans 0, 2, ..., 10: its `lmsego scans`
#   output and odometry lines equal the expected files (made without lmsego;
#   see host_tests/data/carmen/README.md), and --stride 1 is the
#   default. replay --scan-step 2 numbers its pairs 0 2, 2 4, ..., and takes
#   the stride-2 odometry as its prior: the output changes, while the same
#   increments numbered j = i + 1 (or the stride-2 file at step 1) are
#   ignored and leave it as without a prior.
foreach(var EXE DATA OUT_DIR)
    if(NOT DEFINED ${var})
        message(FATAL_ERROR "stride.cmake: ${var} is not set")
    endif()
endforeach()
file(MAKE_DIRECTORY ${OUT_DIR})
set(log ${DATA}/intel_first12.log)
set(want_odom ${DATA}/intel_first12_stride2.odom)

# --- import ---------------------------------------------------------------
execute_process(COMMAND ${EXE} import-carmen ${log} -o ${OUT_DIR}/s2.lms
                        --stride 2 --odometry ${OUT_DIR}/s2.odom
    RESULT_VARIABLE rc ERROR_VARIABLE err)
if(NOT rc EQUAL 0 OR NOT err MATCHES "scans=6 unsupported=0 unit=cm no_return=81.83 stride=2 read=12;")
    message(FATAL_ERROR "import --stride 2 failed (${rc}): ${err}")
endif()
execute_process(COMMAND ${EXE} scans ${OUT_DIR}/s2.lms OUTPUT_VARIABLE scans RESULT_VARIABLE rc)
file(READ ${DATA}/intel_first12_stride2.scans expected_scans)
if(NOT rc EQUAL 0 OR NOT scans STREQUAL expected_scans)
    message(FATAL_ERROR "scans differ from ${DATA}/intel_first12_stride2.scans")
endif()
file(STRINGS ${OUT_DIR}/s2.odom got REGEX "^[0-9]")
file(STRINGS ${want_odom} want REGEX "^[0-9]")
if(NOT got STREQUAL want)
    message(FATAL_ERROR "odometry differs:\n${got}\nexpected:\n${want}")
endif()
foreach(name default one)
    set(args "")
    if(name STREQUAL "one")
        set(args --stride 1)
    endif()
    execute_process(COMMAND ${EXE} import-carmen ${log} -o ${OUT_DIR}/s1_${name}.lms ${args}
        RESULT_VARIABLE rc ERROR_VARIABLE err)
    if(NOT rc EQUAL 0 OR NOT err MATCHES "scans=12 unsupported=0 unit=cm no_return=81.83;")
        message(FATAL_ERROR "import ${args} failed (${rc}): ${err}")
    endif()
    file(SHA256 ${OUT_DIR}/s1_${name}.lms sha_${name})
endforeach()
if(NOT sha_default STREQUAL sha_one)
    message(FATAL_ERROR "--stride 1 differs from the default")
endif()

# --- replay ---------------------------------------------------------------
# The stride-2 increments renumbered `i/2 i/2+1`: right values, wrong pairs.
file(STRINGS ${want_odom} lines REGEX "^[0-9]")
set(renumbered "")
foreach(line IN LISTS lines)
    if(NOT line MATCHES "^([0-9]+) [0-9]+ (.*)$")
        message(FATAL_ERROR "bad line in ${want_odom}: ${line}")
    endif()
    math(EXPR i "${CMAKE_MATCH_1} / 2")
    math(EXPR j "${i} + 1")
    string(APPEND renumbered "${i} ${j} ${CMAKE_MATCH_2}\n")
endforeach()
file(WRITE ${OUT_DIR}/stride1_numbers.odom "${renumbered}")

# replay(NAME args...): CSV in csv_NAME, pairs in ${OUT_DIR}/NAME.pairs
# (unbounded: keyframes at the default period would be searched over
# several scans within the budget, and the priors are what is tested).
macro(replay name)
    execute_process(COMMAND ${EXE} replay ${OUT_DIR}/s2.lms --pairs ${OUT_DIR}/${name}.pairs
                            --budget none ${ARGN}
        OUTPUT_VARIABLE csv_${name} ERROR_VARIABLE err RESULT_VARIABLE rc)
    if(NOT rc EQUAL 0 OR NOT err MATCHES "scans=6 lines=5 ")
        message(FATAL_ERROR "replay ${ARGN} failed (${rc}): ${err}")
    endif()
endmacro()
replay(none --scan-step 2)
replay(prior --scan-step 2 --prior ${want_odom})
# Priors of other pairs are never used: a file with none of this stream's
# pairs is refused (it was ignored in silence until issue 18).
foreach(case "--scan-step;2;--prior;${OUT_DIR}/stride1_numbers.odom" "--prior;${want_odom}")
    execute_process(COMMAND ${EXE} replay ${OUT_DIR}/s2.lms --budget none ${case}
        OUTPUT_VARIABLE out ERROR_VARIABLE err RESULT_VARIABLE rc)
    if(NOT rc EQUAL 1 OR NOT out STREQUAL "" OR NOT err MATCHES "^lmsego: no prior in '[^\n]*'[^\n]*\n$")
        message(FATAL_ERROR "replay ${case}: expected a refusal, got (${rc}): ${err}")
    endif()
endforeach()
replay(step1)

foreach(name none prior)
    file(STRINGS ${OUT_DIR}/${name}.pairs pairs)
    list(LENGTH pairs n)
    if(NOT n EQUAL 5)
        message(FATAL_ERROR "${name}.pairs: ${n} lines, expected 5")
    endif()
    foreach(k RANGE 4)
        list(GET pairs ${k} pair)
        math(EXPR i "2 * ${k}")
        math(EXPR j "${i} + 2")
        if(NOT pair MATCHES "^${i} ${j} -?[0-9]+\\.[0-9]+ -?[0-9]+\\.[0-9]+ -?[0-9]+\\.[0-9]+$")
            message(FATAL_ERROR "${name}.pairs line ${k}: '${pair}', expected '${i} ${j} ...'")
        endif()
    endforeach()
endforeach()
if(csv_prior STREQUAL csv_none)
    message(FATAL_ERROR "the stride-2 prior changed nothing:\n${csv_prior}")
endif()
file(STRINGS ${OUT_DIR}/step1.pairs pairs)
list(GET pairs 0 first)
if(NOT first MATCHES "^0 1 ")
    message(FATAL_ERROR "step 1 pairs start '${first}', expected '0 1 ...'")
endif()

# --- offset: scans 1, 3, ..., 11 ------------------------------------------
execute_process(COMMAND ${EXE} import-carmen ${log} -o ${OUT_DIR}/s2o1.lms
                        --stride 2 --offset 1 --odometry ${OUT_DIR}/s2o1.odom
    RESULT_VARIABLE rc ERROR_VARIABLE err)
if(NOT rc EQUAL 0 OR NOT err MATCHES "scans=6 unsupported=0 unit=cm no_return=81.83 stride=2 read=12;")
    message(FATAL_ERROR "import --stride 2 --offset 1 failed (${rc}): ${err}")
endif()
file(STRINGS ${OUT_DIR}/s2o1.odom got REGEX "^[0-9]")
list(LENGTH got n)
list(GET got 0 first)
if(NOT n EQUAL 5 OR NOT first MATCHES "^1 3 ")
    message(FATAL_ERROR "offset odometry: ${n} lines starting '${first}', expected 5 from '1 3'")
endif()
foreach(name none prior)
    set(args "")
    if(name STREQUAL "prior")
        set(args --prior ${OUT_DIR}/s2o1.odom)
    endif()
    execute_process(COMMAND ${EXE} replay ${OUT_DIR}/s2o1.lms --scan-step 2 --scan-offset 1
                            --budget none --pairs ${OUT_DIR}/o1_${name}.pairs ${args}
        OUTPUT_VARIABLE csv_o1_${name} RESULT_VARIABLE rc)
    file(STRINGS ${OUT_DIR}/o1_${name}.pairs pairs)
    list(GET pairs 4 last)
    if(NOT rc EQUAL 0 OR NOT last MATCHES "^9 11 ")
        message(FATAL_ERROR "replay --scan-offset 1 (${rc}): last pair '${last}', expected '9 11 ...'")
    endif()
endforeach()
if(csv_o1_prior STREQUAL csv_o1_none)
    message(FATAL_ERROR "the offset stride-2 prior changed nothing")
endif()
message("ok")
