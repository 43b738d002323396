# run_session.cmake: the checks of the session image
# (firmware/target/main_session.c).
#
# -DMODE=target -DEMULATOR=<qemu command, a list ending in -kernel>
#   -DIMAGE=<elf> -DHOST=<host build of the image, or empty> -DOUT=<prefix>
#   Passes when the image exits 0 (its own checks passed), prints its
#   '# session', '# insns_per_scan' and '# stack_bytes' lines (the stack
#   within 3.5 KiB of its 4 KiB), and (with HOST) every other line equals
#   the host program's, byte for byte. Writes OUT.target, OUT.host and
#   OUT.figures (the '#' lines).
#
# -DMODE=replay -DPROGRAM=<host session_image> -DLMSEGO=<host lmsego>
#   -DSTREAM=<the .lms it streams> -DOUT=<prefix>
#   Passes when the program exits 0, its lines are numbered 1, 2, 3, ...,
#   one of them (not among the first 10) is the restart (flags odd:
#   EGO_FLAG_FIRST), and every line before it, header included, equals
#   `lmsego replay --budget default STREAM`'s line with the same number
#   but for time_s, which is the scan's own time on the image's clock
#   (firmware/ego_loop.h, "Scan times from arrival stamps"): there the
#   lines must be as far apart as the replay's (the counted interval).
include(${CMAKE_CURRENT_LIST_DIR}/../../firmware/target/run_image.cmake)
get_filename_component(dir "${OUT}" DIRECTORY)
file(MAKE_DIRECTORY "${dir}")

if(MODE STREQUAL "target")
    lmsego_run_image("${EMULATOR}" "${IMAGE}" "${OUT}" 600)
    if(NOT image_rc EQUAL 0)
        message(FATAL_ERROR "the image exited with '${image_rc}' (1: its own check failed; "
                            "faults: 121-127, see target.h): ${image_err}")
    endif()
    foreach(want "# session scans=[0-9]+" "# insns_per_scan median=[0-9]+ max=[0-9]+")
        if(NOT figures MATCHES "${want}")
            message(FATAL_ERROR "no '${want}' line")
        endif()
    endforeach()
    lmsego_check_stack("${figures}")
    if(HOST STREQUAL "")
        message(STATUS "no LMSEGO_HOST_SESSION_IMAGE: output not compared with the host")
        return()
    endif()
    execute_process(COMMAND "${HOST}" OUTPUT_FILE "${OUT}.host" RESULT_VARIABLE hrc)
    if(NOT hrc EQUAL 0)
        message(FATAL_ERROR "the host session image failed: ${hrc}")
    endif()
    lmsego_csv_text("${OUT}.target" target_text)
    lmsego_csv_text("${OUT}.host" host_text)
    if(NOT target_text STREQUAL host_text)
        file(WRITE "${OUT}.target-csv" "${target_text}")
        file(WRITE "${OUT}.host-csv" "${host_text}")
        message(FATAL_ERROR
            "target output differs from the host's: diff ${OUT}.host-csv ${OUT}.target-csv")
    endif()
    string(LENGTH "${host_text}" n)
    message(STATUS "identical to the host (${n} bytes)")
elseif(MODE STREQUAL "replay")
    execute_process(COMMAND "${PROGRAM}" OUTPUT_FILE "${OUT}.program" RESULT_VARIABLE prc)
    if(NOT prc EQUAL 0)
        file(STRINGS "${OUT}.program" failed REGEX "^# check failed")
        message(FATAL_ERROR "${PROGRAM} exited with '${prc}': ${failed}")
    endif()
    # The live core runs within the sensor-rate budget (ego_live_defaults).
    execute_process(COMMAND "${LMSEGO}" replay --budget default "${STREAM}"
        OUTPUT_FILE "${OUT}.replay" ERROR_QUIET RESULT_VARIABLE rrc)
    if(NOT rrc EQUAL 0)
        message(FATAL_ERROR "lmsego replay failed: ${rrc}")
    endif()
    file(STRINGS "${OUT}.program" lines REGEX "^[^#]")
    file(STRINGS "${OUT}.replay" replay_lines)
    list(LENGTH lines n)
    list(LENGTH replay_lines n_replay)
    if(n LESS 12)
        message(FATAL_ERROR "only ${n} CSV lines")
    endif()
    # Numbered 1, 2, 3, ...; the first line flagged FIRST is the restart.
    set(restart 0)
    math(EXPR last "${n} - 1")
    foreach(i RANGE 1 ${last})
        list(GET lines ${i} line)
        string(REPLACE "," ";" fields "${line}")
        list(GET fields 0 scan)
        list(GET fields 8 flags)
        if(NOT scan EQUAL i)
            message(FATAL_ERROR "line ${i} is scan ${scan}: ${line}")
        endif()
        math(EXPR first "${flags} % 2")
        if(first EQUAL 1 AND restart EQUAL 0)
            set(restart ${i})
        endif()
    endforeach()
    if(restart LESS 10)
        message(FATAL_ERROR "no restart line after the first 10 (found: ${restart})")
    endif()
    if(restart GREATER_EQUAL n_replay)
        message(FATAL_ERROR "the replay has ${n_replay} lines, the restart is line ${restart}")
    endif()
    math(EXPR before "${restart} - 1")
    # time_s in microseconds (six decimals).
    function(line_time_us line var)
        string(REPLACE "," ";" f "${line}")
        list(GET f 1 t)
        string(REPLACE "." "" t "${t}")
        math(EXPR t "${t} + 0")
        set(${var} ${t} PARENT_SCOPE)
    endfunction()
    foreach(i RANGE 0 ${before})
        list(GET lines ${i} a)
        list(GET replay_lines ${i} b)
        if(i GREATER 0)
            line_time_us("${a}" ta)
            line_time_us("${b}" tb)
            if(i EQUAL 1)
                set(ta1 ${ta})
                set(tb1 ${tb})
            endif()
            math(EXPR da "${ta} - ${ta1}")
            math(EXPR db "${tb} - ${tb1}")
            if(NOT da EQUAL db)
                message(FATAL_ERROR "line ${i} is ${da} us after line 1, the replay's ${db}:\n  ${a}\n  ${b}")
            endif()
            string(REGEX REPLACE "^([^,]*),[^,]*," "\\1,," a "${a}")
            string(REGEX REPLACE "^([^,]*),[^,]*," "\\1,," b "${b}")
        endif()
        if(NOT a STREQUAL b)
            message(FATAL_ERROR "line ${i} differs from the replay's:\n  ${a}\n  ${b}")
        endif()
    endforeach()
    message(STATUS "${n} lines; the ${restart} before the restart equal lmsego replay's but for their times, as far apart")
else()
    message(FATAL_ERROR "MODE must be target or replay")
endif()
