# POSIX serial port and pseudo-terminal (driver/posix), and the recording
# file format of the host tool (firmware/host/recording.c, read back through
# stream_file.c, both compiled in directly). Included from CMakeLists.txt.
if(TARGET lms_posix)
    lmsego_add_unit_test(test_lms_posix test_lms_posix.c)
    target_link_libraries(test_lms_posix PRIVATE lms_posix)
    # mkdtemp, TIOCGEXCL, CRTSCTS in the test itself.
    target_compile_definitions(test_lms_posix PRIVATE _GNU_SOURCE)
endif()

# The recording format: writer and reader compiled in directly (POSIX:
# mkdtemp, pipe).
if(NOT UNIX)
    return()
endif()
set(LMSEGO_HOST_DIR ${PROJECT_SOURCE_DIR}/firmware/host)
set(LMSEGO_REC_OUT_DIR ${CMAKE_CURRENT_BINARY_DIR}/recording_out)
lmsego_add_unit_test(test_recording test_recording.c
    ${LMSEGO_HOST_DIR}/recording.c ${LMSEGO_HOST_DIR}/stream_file.c
    ${LMSEGO_HOST_DIR}/play_timing.c)
target_include_directories(test_recording PRIVATE ${LMSEGO_HOST_DIR})
# mkdtemp, pipe, dup2, fstat/fileno in stream_file.c.
target_compile_definitions(test_recording PRIVATE _POSIX_C_SOURCE=200809L
    LMSEGO_DATA_DIR="${PROJECT_SOURCE_DIR}/host_tests/data"
    LMSEGO_REC_OUT_DIR="${LMSEGO_REC_OUT_DIR}")
# It leaves recordings behind for the CLI tests below.
set_tests_properties(test_recording PROPERTIES FIXTURES_SETUP lmsego_recordings)

# lmsego stats / scans / replay on recordings (label "cli"): the same
# output as on the raw streams they were made from.
if(TARGET lmsego)
    set(rec_script ${LMSEGO_HOST_DIR}/tests/run_cli.cmake)
    set(rec_data ${PROJECT_SOURCE_DIR}/host_tests/data)
    set(room ${rec_data}/recordings/room_181_mm)
    add_test(NAME cli_recording_stats
        COMMAND ${CMAKE_COMMAND} -DEXE=$<TARGET_FILE:lmsego> -DARG1=stats
                -DARG2=${LMSEGO_REC_OUT_DIR}/room_181_mm.lmsrec
                -DEXPECT_STDOUT_FILE=${room}.stats -DEXPECT_STDERR_EMPTY=ON -P ${rec_script})
    add_test(NAME cli_recording_scans_stdin
        COMMAND ${CMAKE_COMMAND} -DEXE=$<TARGET_FILE:lmsego> -DARG1=scans -DARG2=-
                -DSTDIN_FILE=${LMSEGO_REC_OUT_DIR}/room_181_mm.lmsrec
                -DEXPECT_STDOUT_FILE=${room}.scans -DEXPECT_STDERR_EMPTY=ON -P ${rec_script})
    add_test(NAME cli_recording_bad
        COMMAND ${CMAKE_COMMAND} -DEXE=$<TARGET_FILE:lmsego> -DARG1=stats
                -DARG2=${LMSEGO_REC_OUT_DIR}/backwards.lmsrec
                -DEXPECT_RC=1 -DSTDERR_ONE_LINE=ON
                "-DSTDERR_REGEX=bad recording '.*backwards\\.lmsrec': block time goes backwards at byte 20"
                -P ${rec_script})
    add_test(NAME cli_recording_bad_replay
        COMMAND ${CMAKE_COMMAND} -DEXE=$<TARGET_FILE:lmsego> -DARG1=replay
                -DARG2=${LMSEGO_REC_OUT_DIR}/backwards.lmsrec
                -DEXPECT_RC=1 -DSTDERR_ONE_LINE=ON
                "-DSTDERR_REGEX=bad recording '.*backwards\\.lmsrec': block time goes backwards at byte 20"
                -P ${rec_script})
    # replay --times index (the recording's made-up arrival times left
    # aside): stdout and stderr identical to the raw stream's.
    add_test(NAME cli_recording_replay
        COMMAND sh -c "\"$0\" replay \"$1\" >\"$3.raw\" 2>&1; \"$0\" replay --times index \"$2\" >\"$3.rec\" 2>&1; cmp \"$3.raw\" \"$3.rec\" && grep -q '^1,' \"$3.rec\""
                $<TARGET_FILE:lmsego> ${rec_data}/sequences/table2_361_cm.lms
                ${LMSEGO_REC_OUT_DIR}/table2_361_cm.lmsrec ${LMSEGO_REC_OUT_DIR}/replay)
    set_tests_properties(cli_recording_stats cli_recording_scans_stdin cli_recording_bad
        cli_recording_bad_replay PROPERTIES LABELS "cli" TIMEOUT 60 FIXTURES_REQUIRED lmsego_recordings)
    # Two whole replays of the Table 2 pair (13 s under ASan): e2e.
    set_tests_properties(cli_recording_replay PROPERTIES LABELS "cli;e2e" TIMEOUT 300
        FIXTURES_REQUIRED lmsego_recordings)
endif()
