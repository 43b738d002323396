# Portability check: the portable core must compile for a Cortex-M3 with
# arm-none-eabi-gcc, warnings as errors, and only the target's own headers
# (no host include paths). Registered as the ctest test `portable_cortex_m3`.
find_program(LMSEGO_ARM_GCC arm-none-eabi-gcc)
if(NOT LMSEGO_ARM_GCC)
    if(LMSEGO_REQUIRE_CROSS)
        message(FATAL_ERROR "arm-none-eabi-gcc not found (LMSEGO_REQUIRE_CROSS is ON)")
    endif()
    message(WARNING "arm-none-eabi-gcc not found: the portability check is not registered")
    return()
endif()

set(LMSEGO_PORTABLE_SOURCES ${LMS_DRIVER_SOURCES_ABS} ${LMS_ESTIMATOR_SOURCES_ABS}
    ${EGO_FIRMWARE_SOURCES_ABS} ${PROJECT_SOURCE_DIR}/driver/sim/lms_sim.c)
add_test(NAME portable_cortex_m3
    COMMAND ${CMAKE_COMMAND}
        -DCC=${LMSEGO_ARM_GCC}
        "-DSOURCES=${LMSEGO_PORTABLE_SOURCES}"
        "-DINCLUDE_DIRS=${PROJECT_SOURCE_DIR}/driver;${PROJECT_SOURCE_DIR}/driver/sim;${PROJECT_SOURCE_DIR}/estimator;${PROJECT_SOURCE_DIR}/firmware"
        -DOUT_DIR=${CMAKE_BINARY_DIR}/portable_cortex_m3
        -P ${PROJECT_SOURCE_DIR}/cmake/compile_portable.cmake)
set_tests_properties(portable_cortex_m3 PROPERTIES LABELS "portability")

# The estimator on its own: its sources compile with nothing on the include
# path but estimator/ (and the cross compiler's C headers), so it needs no
# header of the driver or the firmware: any 2-D range sensor can feed it.
add_test(NAME estimator_standalone
    COMMAND ${CMAKE_COMMAND}
        -DCC=${LMSEGO_ARM_GCC}
        "-DSOURCES=${LMS_ESTIMATOR_SOURCES_ABS}"
        "-DINCLUDE_DIRS=${PROJECT_SOURCE_DIR}/estimator"
        -DOUT_DIR=${CMAKE_BINARY_DIR}/estimator_standalone
        -P ${PROJECT_SOURCE_DIR}/cmake/compile_portable.cmake)
set_tests_properties(estimator_standalone PROPERTIES LABELS "portability" TIMEOUT 120)
