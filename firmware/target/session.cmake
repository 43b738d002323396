# session.cmake: included from CMakeLists.txt (cross builds).
#
# The firmware with the session: main_session.c runs the live core
# (firmware/ego_live.h: receive ring, session, loop) against the simulated
# LMS 2xx in the same image (docs/firmware.md). The image session_image
# and two ctest tests (label "target"):
# - target_session: runs it under QEMU; it must exit 0 (its own checks:
#   bring-up, the power cycle recovered, the clean stop), print its
#   measurements, and every other line must equal the host build's output
#   (LMSEGO_HOST_SESSION_IMAGE: a host build's bin/session_image, from
#   host_tests/session_image; without it the output is not compared);
# - target_budget_session: the memory budgets of the whole loop with the
#   session (budget.cmake), the simulator, the scene and the measurement
#   buffer left out; also reported after every build of the image.
set(LMSEGO_HOST_SESSION_IMAGE "" CACHE FILEPATH
    "Host build of the session image (host_tests/session_image) to compare the target's output with")

# The scene: the campus drive, embedded as the replay images embed it.
set(session_scene ${PROJECT_SOURCE_DIR}/host_tests/data/sequences/campus_181_cm.lms)
set(session_scene_c ${CMAKE_CURRENT_BINARY_DIR}/session_scene_stream.c)
add_custom_command(OUTPUT ${session_scene_c}
    COMMAND ${CMAKE_COMMAND} -DIN=${session_scene} -DOUT=${session_scene_c}
            -P ${PROJECT_SOURCE_DIR}/cmake/bin2c.cmake
    DEPENDS ${session_scene} ${PROJECT_SOURCE_DIR}/cmake/bin2c.cmake
    COMMENT "Embedding the session image's scene")
add_library(session_scene OBJECT ${session_scene_c})

lmsego_target_image(session_image ${CMAKE_CURRENT_SOURCE_DIR}/main_session.c
    ${CMAKE_CURRENT_SOURCE_DIR}/report.c $<TARGET_OBJECTS:session_scene>)
target_link_libraries(session_image PRIVATE ego_firmware lms_sim)

add_test(NAME target_session
    COMMAND ${CMAKE_COMMAND} -DMODE=target
        "-DEMULATOR=${CMAKE_CROSSCOMPILING_EMULATOR}"
        -DIMAGE=$<TARGET_FILE:session_image>
        -DHOST=${LMSEGO_HOST_SESSION_IMAGE}
        -DOUT=${CMAKE_BINARY_DIR}/target_out/session_image
        -P ${PROJECT_SOURCE_DIR}/host_tests/session_image/run_session.cmake)
set_tests_properties(target_session PROPERTIES LABELS "target" TIMEOUT 300)

# Budgets: everything of the simulated board is left out, by object file
# (the simulator, the scene, report.c's printing of figures) and by symbol
# (main_session.c's sim_* glue and state, the image's own measurement and
# checks image_* and their buffer insns), summed from the map file.
set(session_budget_args -DSIZE=${LMSEGO_ARM_SIZE} -DNM=${LMSEGO_ARM_NM}
    -DIMAGE=$<TARGET_FILE:session_image> -DSU_DIR=${CMAKE_BINARY_DIR}
    -DOUT=${CMAKE_BINARY_DIR}/budget_session.txt -DFLASH_LIMIT=${LMSEGO_FLASH_LIMIT}
    -DMAP=${CMAKE_BINARY_DIR}/bin/session_image.map
    "-DEXCLUDE_SOURCES=lms_sim[.]c|session_scene_stream[.]c|report[.]c"
    "-DEXCLUDE_SYMBOLS=sim_[A-Za-z0-9_]*|image_[A-Za-z0-9_]*|insns")
add_custom_command(TARGET session_image POST_BUILD
    COMMAND ${CMAKE_COMMAND} ${session_budget_args} -P ${CMAKE_CURRENT_SOURCE_DIR}/budget.cmake
    VERBATIM)
add_test(NAME target_budget_session
    COMMAND ${CMAKE_COMMAND} ${session_budget_args} -DCHECK=ON
            -P ${CMAKE_CURRENT_SOURCE_DIR}/budget.cmake)
set_tests_properties(target_budget_session PROPERTIES LABELS "target")

# Worst-case stack through the call graph (measure.cmake), once the table
# of indirect calls (stack_indirect.txt) lists the session image's: the
# core's HAL calls, the session's I/O hooks and the simulator's scene.
set_property(DIRECTORY APPEND PROPERTY CMAKE_CONFIGURE_DEPENDS
    ${CMAKE_CURRENT_SOURCE_DIR}/stack_indirect.txt)
file(STRINGS ${CMAKE_CURRENT_SOURCE_DIR}/stack_indirect.txt session_indirect REGEX "^session_write:")
if(session_indirect AND COMMAND lmsego_stack_check)
    lmsego_stack_check(session_image)
endif()

# The same board in real time (docs/firmware.md): the core in deferred mode,
# its line service in the SysTick interrupt every millisecond of a 168 MHz
# part's time, the estimator in the main loop on the newest scan. Its own
# checks decide (nothing dropped, the restart, the clean stop, every scan
# estimated or skipped); its output is not the host's.
# Its own ego_live.c, deferred mode only (EGO_LIVE_DEFERRED_ONLY: the
# estimator is not on the interrupt's call path, so the worst-case stack,
# interrupt on top of main loop, is exact); the linker takes it before the
# library's.
# lmsego_session_irq_image(IMAGE TEST [DEFINITIONS...]): that board as
# IMAGE, run by ctest TEST, with its worst-case stack checked.
function(lmsego_session_irq_image image test)
    lmsego_target_image(${image} ${CMAKE_CURRENT_SOURCE_DIR}/main_session.c
        ${CMAKE_CURRENT_SOURCE_DIR}/report.c ${PROJECT_SOURCE_DIR}/firmware/ego_live.c
        $<TARGET_OBJECTS:session_scene>)
    target_compile_definitions(${image} PRIVATE SESSION_INTERRUPTS EGO_LIVE_DEFERRED_ONLY ${ARGN})
    target_link_libraries(${image} PRIVATE ego_firmware lms_sim)
    add_test(NAME ${test}
        COMMAND ${CMAKE_COMMAND} -DMODE=target
            "-DEMULATOR=${CMAKE_CROSSCOMPILING_EMULATOR}"
            -DIMAGE=$<TARGET_FILE:${image}>
            -DHOST=
            -DOUT=${CMAKE_BINARY_DIR}/target_out/${image}
            -P ${PROJECT_SOURCE_DIR}/host_tests/session_image/run_session.cmake)
    set_tests_properties(${test} PROPERTIES LABELS "target" TIMEOUT 300)
    if(session_indirect AND COMMAND lmsego_stack_check)
        lmsego_stack_check(${image})
    endif()
endfunction()
lmsego_session_irq_image(session_irq_image target_session_irq)

