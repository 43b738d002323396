# cmake -P script: `lmsego <command> --help` for every command states its
# input, its options and its exit status, and no longer claims that FILE
# is a raw telegram stream where it is not one (issue 18); replay's and
# import-carmen's say what was missing before: --period's range, the
# columns and flags, --no-return's default and none.
foreach(var EXE)
    if(NOT DEFINED ${var})
        message(FATAL_ERROR "help.cmake: ${var} is not set")
    endif()
endforeach()
set(failures "")
foreach(cmd stats scans replay frames import-carmen run record sim play)
    execute_process(COMMAND ${EXE} ${cmd} --help
        RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
    if(NOT rc EQUAL 0 OR NOT err STREQUAL "")
        string(APPEND failures "  ${cmd}: exit ${rc}, stderr '${err}'\n")
    endif()
    foreach(part "^usage: lmsego ${cmd} " "\ninput" "\noptions" "\nexit status: 0 ")
        if(NOT out MATCHES "${part}")
            string(APPEND failures "  ${cmd}: no '${part}' in its help\n")
        endif()
    endforeach()
    if(out MATCHES "FILE is a raw recorded telegram stream")
        string(APPEND failures "  ${cmd}: still the old FILE line\n")
    endif()
    set(help_${cmd} "${out}")
endforeach()
foreach(want "--period S +seconds between scans.*0\\.001 \\.\\. 10" "flags +EGO_FLAG_" "2048 suspect"
        "cov_xx" "--budget none\\|default\\|U" "--prior FILE" "--mount X,Y,DEG .*m, m, deg"
        "ends inside a telegram")
    if(NOT help_replay MATCHES "${want}")
        string(APPEND failures "  replay: no '${want}' in its help\n")
    endif()
endforeach()
foreach(want "LOG +a CARMEN laser log" "--no-return M\\|none" "default: the log's largest reading"
        "none: every reading is a return")
    if(NOT help_import-carmen MATCHES "${want}")
        string(APPEND failures "  import-carmen: no '${want}' in its help\n")
    endif()
endforeach()
if(NOT help_frames MATCHES "binary ego-motion frames" OR NOT help_frames MATCHES "flags +EGO_FLAG_")
    string(APPEND failures "  frames: its help names neither its input nor its columns\n")
endif()
if(NOT failures STREQUAL "")
    message(FATAL_ERROR "help texts:\n${failures}")
endif()
message("ok")
