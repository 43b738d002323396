# cmake -P script: the binary ego-motion frames both ways, for one telegram
# stream.
#   1. `replay STREAM` gives the reference CSV;
#   2. `replay --frames F STREAM` prints the same CSV and writes F, one
#      66-byte frame per CSV line;
#   3. `frames F` and `frames - < F` print the reference byte for byte, with
#      a clean decoder summary;
#   4. a damaged stream built from F (garbage, a cut frame, a complete frame
#      with a bad CRC, an unfinished frame at the end, F three times in
#      between) still gives every intact line, and the summary counts the
#      damage: every garbage byte skipped, CRC and length errors, one
#      truncated candidate.
# No shell: the damage is written with file(WRITE) (bytes without NUL) and
# joined with `cmake -E cat`.
#
#   cmake -DEXE=lmsego -DSTREAM=x.lms -DOUT_DIR=dir [-DEXTRA=replay;options]
#         -P frames_roundtrip.cmake
cmake_minimum_required(VERSION 3.21)
foreach(var EXE STREAM OUT_DIR)
    if(NOT DEFINED ${var})
        message(FATAL_ERROR "frames_roundtrip.cmake: ${var} is not set")
    endif()
endforeach()
file(MAKE_DIRECTORY ${OUT_DIR})
set(bin ${OUT_DIR}/frames.bin)
set(frame_size 66)

# run(OUT ERR [INPUT file] COMMAND ...): runs, fails unless the exit code is 0.
function(run out_var err_var)
    cmake_parse_arguments(PARSE_ARGV 2 r "" "INPUT" "COMMAND")
    if(DEFINED r_INPUT)
        execute_process(COMMAND ${r_COMMAND} INPUT_FILE ${r_INPUT}
            OUTPUT_VARIABLE out ERROR_VARIABLE err RESULT_VARIABLE rc)
    else()
        execute_process(COMMAND ${r_COMMAND}
            OUTPUT_VARIABLE out ERROR_VARIABLE err RESULT_VARIABLE rc)
    endif()
    if(NOT rc STREQUAL "0")
        string(REPLACE ";" " " shown "${r_COMMAND}")
        message(FATAL_ERROR "${shown}: exit ${rc}: ${err}")
    endif()
    set(${out_var} "${out}" PARENT_SCOPE)
    set(${err_var} "${err}" PARENT_SCOPE)
endfunction()

function(expect_same what got expected)
    if(NOT got STREQUAL expected)
        file(WRITE ${OUT_DIR}/${what}.got "${got}")
        file(WRITE ${OUT_DIR}/${what}.expected "${expected}")
        message(FATAL_ERROR "${what}: stdout differs from the reference (see ${OUT_DIR}/${what}.*)")
    endif()
endfunction()

# 1-2. The reference, and the same with frames.
run(csv err COMMAND ${EXE} replay ${EXTRA} ${STREAM})
run(csv_frames err COMMAND ${EXE} replay ${EXTRA} --frames ${bin} ${STREAM})
expect_same(replay_frames "${csv_frames}" "${csv}")
string(REGEX MATCHALL "\n" newlines "${csv}")
list(LENGTH newlines n_lines)
math(EXPR n "${n_lines} - 1") # the header
if(n LESS 1)
    message(FATAL_ERROR "${STREAM}: no motion lines to compare")
endif()
file(SIZE ${bin} size)
math(EXPR expect_size "${n} * ${frame_size}")
if(NOT size EQUAL expect_size)
    message(FATAL_ERROR "${bin}: ${size} bytes, expected ${n} frames of ${frame_size}")
endif()

# 3. Back to CSV, from the file and from stdin.
set(clean "^lmsego: frames: frames=${n} crc_errors=0 length_errors=0 truncated=0 bytes_skipped=0\n$")
run(out err COMMAND ${EXE} frames ${bin})
expect_same(frames "${out}" "${csv}")
if(NOT err MATCHES "${clean}")
    message(FATAL_ERROR "frames summary: ${err}")
endif()
run(out err INPUT ${bin} COMMAND ${EXE} frames -)
expect_same(frames_stdin "${out}" "${csv}")
if(NOT err MATCHES "${clean}")
    message(FATAL_ERROR "frames - summary: ${err}")
endif()

# 4. Damage. Pieces (none holds a NUL, so file(WRITE) can make them):
#    junk  "junk" E5 01, then F's first start byte: a wrong length byte;
#    cut   E5 01 25 and 17 bytes of a frame: it swallows the start of the
#          next frame, fails its CRC, and the decoder finds that frame again;
#    bad   a whole frame of 0x41 with the CRC bytes "ZZ": a CRC error;
#    tail  E5 01 25 41 at the very end: truncated.
string(ASCII 229 1 e5_01)
string(ASCII 229 1 37 e5_01_25)
file(WRITE ${OUT_DIR}/junk.bin "junk${e5_01}")
string(ASCII 127 del)
string(REPEAT "${del}" 17 body)
file(WRITE ${OUT_DIR}/cut.bin "${e5_01_25}${body}")
string(REPEAT "A" 37 body)
file(WRITE ${OUT_DIR}/bad.bin "${e5_01_25}${body}ZZ")
file(WRITE ${OUT_DIR}/tail.bin "${e5_01_25}A")
set(skipped 72) # 6 + 20 + 42 + 4
set(damaged ${OUT_DIR}/damaged.bin)
execute_process(COMMAND ${CMAKE_COMMAND} -E cat ${OUT_DIR}/junk.bin ${bin} ${OUT_DIR}/cut.bin
                        ${bin} ${OUT_DIR}/bad.bin ${bin} ${OUT_DIR}/tail.bin
    OUTPUT_FILE ${damaged} RESULT_VARIABLE rc)
file(SIZE ${damaged} size)
math(EXPR expect_size "3 * ${n} * ${frame_size} + ${skipped}")
if(NOT rc EQUAL 0 OR NOT size EQUAL expect_size)
    message(FATAL_ERROR "building ${damaged} failed (${rc}, ${size} bytes)")
endif()
string(LENGTH "scan,time_s,dx_m,dy_m,dtheta_rad,vx_mps,vy_mps,omega_radps,flags,iterations,matches,cov_xx,cov_xy,cov_xt,cov_yy,cov_yt,cov_tt\n"
       header_len)
string(SUBSTRING "${csv}" ${header_len} -1 lines)
run(out err COMMAND ${EXE} frames ${damaged})
expect_same(frames_damaged "${out}" "${csv}${lines}${lines}")
math(EXPR n3 "3 * ${n}")
if(NOT err MATCHES "^lmsego: frames: frames=${n3} crc_errors=([0-9]+) length_errors=([0-9]+) truncated=1 bytes_skipped=${skipped}\n$")
    message(FATAL_ERROR "damaged frames summary: ${err}")
endif()
if(CMAKE_MATCH_1 LESS 2 OR CMAKE_MATCH_2 LESS 1)
    message(FATAL_ERROR "damaged frames: expected >= 2 CRC and >= 1 length errors: ${err}")
endif()
message("ok: ${n} frames both ways; damaged stream: ${err}")
