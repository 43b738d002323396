# world_test.cmake - one lmsworld test (see CMakeLists.txt beside it).
#
#   cmake -DMODE=m -DNAME=n -DLMSWORLD=path -DWORLD_CHECK=path -DLMSEGO=path
#         -DOUT_DIR=dir -DSHIPPED_DIR=dir [-DKEY=value ...]
#         -DARG1=.. -DARG2=.. (lmsworld options, one per variable)
#         -P world_test.cmake
#
# MODE determinism  run twice, stream / truth / poses byte-identical
#      seed         seeds 1 and 2 differ (noise on), seed 1 twice does not
#      pairs        truth consistent with the poses (SCANS, PERIOD, SKIP)
#      stats        `lmsego stats` = SCANS scans, SCANS + 1 telegrams, no error
#      decode       `lmsego scans` values = cast ranges (SCENARIO RES UNIT
#                   MAX_RANGE SKIP, TIMING instant (default) or lms; mm
#                   streams are read in mode 0F)
#      timing       ARGS with --timing lms: the stream differs from instant
#                   timing's, the truth and the poses do not
#      table2       the single truth line is the paper's Table 2 pair
#      usage        lmsworld exits EXPECT_RC and writes no stream
#      regen        outputs equal SHIPPED_DIR/NAME.{lms,pairs,tum}
#      busy_regen   outputs with --objects equal BUSY_DIR/NAME.{lms,pairs,tum,objects}
#                   (NAME without its busy_regen_ prefix)
#      objects      --objects checked by world_check objects (SCENARIO RES
#                   MAX_RANGE SKIP, TIMING instant (default) or lms, VEL_TOL);
#                   with MIN_STILL also world_check standstill
# OBJECTS=1 (any mode that generates) also writes and, for determinism,
# compares the --objects file.
#      budget       `lmsego replay` within the default budget (REPLAY_MODE:
#                   its --mode; REPLAY_TIMING: its --sweep, default instant) fails at
#                   most MAX_FAILED pairs (or at least MIN_FAILED), aperture
#                   lines' translation excluded (PYTHON, SCRIPT: pairs_error.py)
#      trust        the same replay has no silent failure (NEES: nees.py) and,
#                   with REQUIRE_FLAG, at least MIN_SHARE of its lines carry one
#                   of those flags
cmake_minimum_required(VERSION 3.21)
foreach(var MODE NAME LMSWORLD WORLD_CHECK LMSEGO OUT_DIR SHIPPED_DIR BUSY_DIR)
    if(NOT DEFINED ${var})
        message(FATAL_ERROR "world_test.cmake: ${var} is not set")
    endif()
endforeach()

set(args "")
foreach(i RANGE 1 30)
    if(DEFINED ARG${i})
        list(APPEND args "${ARG${i}}")
    endif()
endforeach()

set(dir ${OUT_DIR}/${NAME})
file(REMOVE_RECURSE ${dir})
file(MAKE_DIRECTORY ${dir})

# generate(prefix extra-args...): lmsworld ARGS -o prefix.lms --truth
# prefix.pairs --poses prefix.tum (and --objects prefix.objects with
# OBJECTS), failing the test on a nonzero exit.
function(generate prefix)
    set(objects_args "")
    if(OBJECTS)
        set(objects_args --objects ${prefix}.objects)
    endif()
    execute_process(
        COMMAND ${LMSWORLD} ${args} ${ARGN} -o ${prefix}.lms --truth ${prefix}.pairs
                --poses ${prefix}.tum ${objects_args}
        RESULT_VARIABLE rc ERROR_VARIABLE err)
    if(NOT rc STREQUAL "0")
        message(FATAL_ERROR "lmsworld failed (${rc}): ${err}")
    endif()
endfunction()

function(run_checked)
    execute_process(COMMAND ${ARGN} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
    if(NOT rc STREQUAL "0")
        message(FATAL_ERROR "${ARGN}\nfailed (${rc}):\n${out}${err}")
    endif()
    message("${out}")
endfunction()

# same(a b): 1 when the files are byte-identical.
function(same a b result)
    execute_process(COMMAND ${CMAKE_COMMAND} -E compare_files ${a} ${b} RESULT_VARIABLE rc)
    if(rc STREQUAL "0")
        set(${result} 1 PARENT_SCOPE)
    else()
        set(${result} 0 PARENT_SCOPE)
    endif()
endfunction()

set(outputs lms pairs tum)
if(MODE STREQUAL "objects" OR MODE STREQUAL "busy_regen")
    set(OBJECTS 1)
endif()
if(OBJECTS)
    list(APPEND outputs objects)
endif()

if(MODE STREQUAL "determinism")
    generate(${dir}/a)
    generate(${dir}/b)
    foreach(ext IN LISTS outputs)
        same(${dir}/a.${ext} ${dir}/b.${ext} ok)
        if(NOT ok)
            message(FATAL_ERROR "two runs gave different .${ext} files")
        endif()
    endforeach()
elseif(MODE STREQUAL "seed")
    generate(${dir}/a --seed 1)
    generate(${dir}/b --seed 1)
    generate(${dir}/c --seed 2)
    same(${dir}/a.lms ${dir}/b.lms ok)
    if(NOT ok)
        message(FATAL_ERROR "seed 1 twice gave different streams")
    endif()
    same(${dir}/a.lms ${dir}/c.lms ok)
    if(ok)
        message(FATAL_ERROR "seeds 1 and 2 gave the same noisy stream")
    endif()
    foreach(ext pairs tum)
        file(STRINGS ${dir}/a.${ext} a_lines REGEX "^[^#]")
        file(STRINGS ${dir}/c.${ext} c_lines REGEX "^[^#]")
        if(NOT a_lines STREQUAL c_lines)
            message(FATAL_ERROR "the seed changed the ground truth (.${ext})")
        endif()
    endforeach()
elseif(MODE STREQUAL "pairs")
    generate(${dir}/s)
    run_checked(${WORLD_CHECK} pairs ${dir}/s.pairs ${dir}/s.tum ${SCANS} ${PERIOD} ${SKIP})
elseif(MODE STREQUAL "stats")
    generate(${dir}/s)
    file(SIZE ${dir}/s.lms bytes)
    math(EXPR telegrams "${SCANS} + 1")
    set(want "telegrams=${telegrams} scans=${SCANS} crc_errors=0 length_errors=0 bytes_skipped=0"
             " resyncs=0 truncated=0 acks=1 naks=0 bytes=${bytes} decode_errors=0\n")
    string(CONCAT want ${want})
    execute_process(COMMAND ${LMSEGO} stats ${dir}/s.lms
        RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
    if(NOT rc STREQUAL "0" OR NOT out STREQUAL want)
        message(FATAL_ERROR "lmsego stats (${rc}) said:\n${out}${err}wanted:\n${want}")
    endif()
elseif(MODE STREQUAL "decode")
    generate(${dir}/s)
    set(mode_args "")
    if(UNIT STREQUAL "mm")
        set(mode_args --mode 0F)
    endif()
    execute_process(COMMAND ${LMSEGO} scans ${mode_args} ${dir}/s.lms
        OUTPUT_FILE ${dir}/s.scans RESULT_VARIABLE rc ERROR_VARIABLE err)
    if(NOT rc STREQUAL "0")
        message(FATAL_ERROR "lmsego scans failed (${rc}): ${err}")
    endif()
    if(NOT DEFINED TIMING)
        set(TIMING instant)
    endif()
    run_checked(${WORLD_CHECK} decode ${dir}/s.scans ${SCENARIO} ${RES} ${UNIT} ${MAX_RANGE}
        ${SKIP} ${TIMING})
elseif(MODE STREQUAL "timing")
    generate(${dir}/a)
    generate(${dir}/b --timing lms)
    same(${dir}/a.lms ${dir}/b.lms ok)
    if(ok)
        message(FATAL_ERROR "--timing lms gave the same stream under motion")
    endif()
    foreach(ext pairs tum)
        file(STRINGS ${dir}/a.${ext} a_lines REGEX "^[^#]")
        file(STRINGS ${dir}/b.${ext} b_lines REGEX "^[^#]")
        if(NOT a_lines STREQUAL b_lines)
            message(FATAL_ERROR "--timing lms changed the ground truth (.${ext})")
        endif()
        file(STRINGS ${dir}/b.${ext} b_head LIMIT_COUNT 1)
        if(NOT b_head MATCHES " --timing lms$")
            message(FATAL_ERROR "the .${ext} header does not say --timing lms: ${b_head}")
        endif()
    endforeach()
    file(SIZE ${dir}/a.lms a_size)
    file(SIZE ${dir}/b.lms b_size)
    if(NOT a_size EQUAL b_size)
        message(FATAL_ERROR "--timing lms changed the stream's size: ${a_size} ${b_size}")
    endif()
elseif(MODE STREQUAL "table2")
    generate(${dir}/s)
    run_checked(${WORLD_CHECK} table2 ${dir}/s.pairs)
elseif(MODE STREQUAL "usage")
    execute_process(COMMAND ${LMSWORLD} ${args}
        WORKING_DIRECTORY ${dir} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
    if(NOT rc STREQUAL "${EXPECT_RC}")
        message(FATAL_ERROR "lmsworld exited ${rc}, wanted ${EXPECT_RC}: ${out}${err}")
    endif()
    if(err STREQUAL "" OR NOT out STREQUAL "")
        message(FATAL_ERROR "wanted a message on stderr only: stdout '${out}' stderr '${err}'")
    endif()
    file(GLOB written ${dir}/*)
    if(written)
        message(FATAL_ERROR "lmsworld wrote files after a usage error: ${written}")
    endif()
elseif(MODE STREQUAL "regen" OR MODE STREQUAL "busy_regen")
    # The shipped sequences (regen: ../data/sequences, .lms .pairs .tum;
    # busy_regen: ../data/busy, with its .objects too).
    string(REGEX REPLACE "^(busy_)?regen_" "" base ${NAME})
    set(shipped ${SHIPPED_DIR})
    set(exts lms pairs tum)
    if(MODE STREQUAL "busy_regen")
        set(shipped ${BUSY_DIR})
        set(exts ${outputs})
    endif()
    generate(${dir}/${base})
    set(failed "")
    foreach(ext IN LISTS exts)
        same(${dir}/${base}.${ext} ${shipped}/${base}.${ext} ok)
        if(NOT ok)
            string(APPEND failed " ${base}.${ext}")
        endif()
    endforeach()
    if(NOT failed STREQUAL "")
        message(FATAL_ERROR "regenerated files differ from the shipped ones:${failed}\n"
            "(regenerated into ${dir})")
    endif()
elseif(MODE STREQUAL "objects")
    generate(${dir}/s)
    if(NOT DEFINED TIMING)
        set(TIMING instant)
    endif()
    if(NOT DEFINED VEL_TOL)
        set(VEL_TOL 0.02)
    endif()
    run_checked(${WORLD_CHECK} objects ${dir}/s.objects ${SCENARIO} ${RES} ${MAX_RANGE} ${SKIP}
        ${TIMING} ${VEL_TOL})
    if(DEFINED MIN_STILL)
        run_checked(${WORLD_CHECK} standstill ${dir}/s.pairs ${dir}/s.objects ${MIN_STILL})
    endif()
elseif(MODE STREQUAL "budget" OR MODE STREQUAL "trust")
    generate(${dir}/s)
    set(mode_args "")
    if(DEFINED REPLAY_MODE)
        set(mode_args --mode ${REPLAY_MODE})
    endif()
    # lmsworld casts every value at once unless asked for the LMS's timing
    # (then REPLAY_TIMING=lms); REPLAY_TIMING=instant on an LMS-timed
    # stream replays it without de-skewing.
    if(NOT DEFINED REPLAY_TIMING)
        set(REPLAY_TIMING instant)
    endif()
    execute_process(COMMAND ${LMSEGO} replay ${mode_args} --sweep ${REPLAY_TIMING} --budget default
        ${dir}/s.lms OUTPUT_FILE ${dir}/s.csv RESULT_VARIABLE rc ERROR_VARIABLE err)
    if(NOT rc STREQUAL "0")
        message(FATAL_ERROR "lmsego replay failed (${rc}): ${err}")
    endif()
    if(MODE STREQUAL "budget")
        set(bounds --max-failed ${MAX_FAILED})
        if(DEFINED MIN_FAILED)
            set(bounds --min-failed ${MIN_FAILED})
        endif()
        run_checked(${PYTHON} ${SCRIPT} ${dir}/s.pairs ${dir}/s.csv --exclude-flags 2 ${bounds})
    else()
        set(flag_args "")
        if(DEFINED REQUIRE_FLAG)
            set(flag_args --require-flag ${REQUIRE_FLAG} --min-share ${MIN_SHARE})
        endif()
        run_checked(${PYTHON} ${NEES} ${dir}/s.pairs ${dir}/s.csv --max-silent 0 --list ${flag_args})
    endif()
else()
    message(FATAL_ERROR "world_test.cmake: unknown MODE ${MODE}")
endif()
