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

# lmsego_portable_test(NAME SOURCES INCLUDE_DIRS): compile_portable.cmake
# over SOURCES with only INCLUDE_DIRS (lists) on the path; label
# portability.
function(lmsego_portable_test name sources include_dirs)
    add_test(NAME ${name}
        COMMAND ${CMAKE_COMMAND} -DCC=${LMSEGO_ARM_GCC} "-DSOURCES=${sources}"
            "-DINCLUDE_DIRS=${include_dirs}" -DOUT_DIR=${CMAKE_BINARY_DIR}/${name}
            -P ${PROJECT_SOURCE_DIR}/cmake/compile_portable.cmake)
    set_tests_properties(${name} PROPERTIES LABELS "portability" TIMEOUT 120)
endfunction()

set(LMSEGO_PORTABLE_SOURCES ${LMS_DRIVER_SOURCES_ABS} ${LMS_ESTIMATOR_SOURCES_ABS}
    ${EGO_FIRMWARE_SOURCES_ABS} ${PROJECT_SOURCE_DIR}/driver/sim/lms_sim.c)
lmsego_portable_test(portable_cortex_m3 "${LMSEGO_PORTABLE_SOURCES}"
    "${PROJECT_SOURCE_DIR}/driver;${PROJECT_SOURCE_DIR}/driver/sim;${PROJECT_SOURCE_DIR}/estimator;${PROJECT_SOURCE_DIR}/firmware")

# The estimator on its own: its sources compile with nothing on the include
# path but estimator/ (and the cross compiler's C headers), so it needs no
# header of the driver or the firmware: any 2-D range sensor can feed it.
lmsego_portable_test(estimator_standalone "${LMS_ESTIMATOR_SOURCES_ABS}" "${PROJECT_SOURCE_DIR}/estimator")
