# run_image.cmake: what the cmake -P scripts that run a target image share
# (run_replay.cmake, run_framer.cmake, host_tests/session_image/run_session.cmake).

# Runs IMAGE under EMULATOR (a list ending in -kernel); writes OUT.target
# (all output) and OUT.figures (its '#' lines, also printed). Sets in the
# caller: image_rc (the exit code), image_err (stderr), figures (the '#'
# lines as a list).
function(lmsego_run_image emulator image out timeout)
    get_filename_component(dir "${out}" DIRECTORY)
    file(MAKE_DIRECTORY "${dir}")
    execute_process(COMMAND ${emulator} ${image}
        OUTPUT_FILE "${out}.target" ERROR_VARIABLE err RESULT_VARIABLE rc TIMEOUT ${timeout})
    set(lines "")
    if(EXISTS "${out}.target")
        file(STRINGS "${out}.target" lines REGEX "^#")
    endif()
    file(WRITE "${out}.figures" "")
    foreach(line IN LISTS lines)
        message(STATUS "${line}")
        file(APPEND "${out}.figures" "${line}\n")
    endforeach()
    set(image_rc "${rc}" PARENT_SCOPE)
    set(image_err "${err}" PARENT_SCOPE)
    set(figures "${lines}" PARENT_SCOPE)
endfunction()

# Fails unless the figures hold a '# stack_bytes used=' line within 3.5 KiB:
# the stack section is 4 KiB with .bss below it, so keep a 512-byte margin.
function(lmsego_check_stack figures)
    if(NOT figures MATCHES "# stack_bytes used=([0-9]+)")
        message(FATAL_ERROR "no '# stack_bytes' line")
    endif()
    if(CMAKE_MATCH_1 GREATER 3584)
        message(FATAL_ERROR "stack high-water mark ${CMAKE_MATCH_1} B: above 3.5 KiB of 4 KiB")
    endif()
endfunction()

# The text of a file without its '#' lines (the CSV an image writes).
function(lmsego_csv_text file var)
    file(READ "${file}" text)
    string(REGEX REPLACE "(^|\n)#[^\n]*" "" text "${text}")
    string(REGEX REPLACE "^\n" "" text "${text}")
    set(${var} "${text}" PARENT_SCOPE)
endfunction()
