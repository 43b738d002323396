# cmake -P script: lmsego import-carmen on the plain and the gzip'd excerpt
# must give the same stream, whose `lmsego scans` output and odometry
# increments equal the expected files (made by other implementations; see
# host_tests/data/carmen/README.md).
foreach(var EXE DATA OUT_DIR)
    if(NOT DEFINED ${var})
        message(FATAL_ERROR "import_carmen.cmake: ${var} is not set")
    endif()
endforeach()
file(MAKE_DIRECTORY ${OUT_DIR})
foreach(input intel_first4.log intel_first4.log.gz)
    execute_process(COMMAND ${EXE} import-carmen ${DATA}/${input} -o ${OUT_DIR}/${input}.lms
                            --odometry ${OUT_DIR}/${input}.odom
        RESULT_VARIABLE rc ERROR_VARIABLE err)
    if(NOT rc EQUAL 0 OR NOT err MATCHES "scans=4 unsupported=0 unit=cm no_return=81.83")
        message(FATAL_ERROR "import of ${input} failed (${rc}): ${err}")
    endif()
endforeach()
file(SHA256 ${OUT_DIR}/intel_first4.log.lms plain)
file(SHA256 ${OUT_DIR}/intel_first4.log.gz.lms packed)
if(NOT plain STREQUAL packed)
    message(FATAL_ERROR "plain and gzip'd logs gave different streams")
endif()
execute_process(COMMAND ${EXE} scans ${OUT_DIR}/intel_first4.log.lms
    OUTPUT_VARIABLE scans RESULT_VARIABLE rc)
file(READ ${DATA}/intel_first4.scans expected_scans)
if(NOT rc EQUAL 0 OR NOT scans STREQUAL expected_scans)
    message(FATAL_ERROR "scans differ from ${DATA}/intel_first4.scans")
endif()
file(STRINGS ${OUT_DIR}/intel_first4.log.odom got REGEX "^[0-9]")
file(STRINGS ${DATA}/intel_first4.odom want REGEX "^[0-9]")
if(NOT got STREQUAL want)
    message(FATAL_ERROR "odometry differs:\n${got}\nexpected:\n${want}")
endif()
message("ok")
