# Consumer tests (label consumer; docs/install.md): the project in
# host_tests/consumer/ built against lmsego the three ways a user can,
# by run_consumer.cmake in scratch directories under <build>/consumer:
#   consumer_host_install     installed tree: find_package + pkg-config
#   consumer_host_subdir      add_subdirectory of this source tree
#   consumer_cortex_m3_*      the same two with cmake/arm-none-eabi.cmake
# and `lmsego --version` (label cli). Included from the top-level
# CMakeLists.txt with the host tests.
find_program(LMSEGO_PKG_CONFIG NAMES pkg-config pkgconf)
find_program(LMSEGO_ARM_GCC arm-none-eabi-gcc)
find_program(LMSEGO_ARM_NM arm-none-eabi-nm)

# lmsego_consumer_test(NAME MODE [ARGS...]): ARGS go to run_consumer.cmake.
function(lmsego_consumer_test name mode)
    add_test(NAME consumer_${name}
        COMMAND ${CMAKE_COMMAND}
            -DMODE=${mode}
            -DLMSEGO_SOURCE_DIR=${PROJECT_SOURCE_DIR}
            -DWORK=${CMAKE_BINARY_DIR}/consumer/${name}
            -DGENERATOR=${CMAKE_GENERATOR}
            -DVERSION=${PROJECT_VERSION}
            ${ARGN}
            -P ${CMAKE_CURRENT_FUNCTION_LIST_DIR}/run_consumer.cmake)
    # Each builds lmsego with -j 2.
    set_tests_properties(consumer_${name} PROPERTIES LABELS consumer TIMEOUT 300 PROCESSORS 2)
endfunction()

lmsego_consumer_test(host_install install
    -DC_COMPILER=${CMAKE_C_COMPILER} -DPKG_CONFIG=${LMSEGO_PKG_CONFIG})
lmsego_consumer_test(host_subdir subdir -DC_COMPILER=${CMAKE_C_COMPILER})

if(LMSEGO_ARM_GCC AND LMSEGO_ARM_NM)
    foreach(mode install subdir)
        lmsego_consumer_test(cortex_m3_${mode} ${mode}
            -DTOOLCHAIN=${PROJECT_SOURCE_DIR}/cmake/arm-none-eabi.cmake -DNM=${LMSEGO_ARM_NM})
    endforeach()
elseif(LMSEGO_REQUIRE_CROSS)
    message(FATAL_ERROR "arm-none-eabi-gcc or -nm not found (LMSEGO_REQUIRE_CROSS is ON)")
else()
    message(WARNING "arm-none-eabi-gcc not found: the Cortex-M consumer tests are not registered")
endif()

# lmsego --version: exactly "lmsego <version>\n" on stdout, exit 0.
file(WRITE ${CMAKE_BINARY_DIR}/consumer/cli_version.txt "lmsego ${PROJECT_VERSION}\n")
add_test(NAME cli_version
    COMMAND ${CMAKE_COMMAND} -DEXE=$<TARGET_FILE:lmsego> -DARG1=--version
        -DEXPECT_STDOUT_FILE=${CMAKE_BINARY_DIR}/consumer/cli_version.txt -DEXPECT_STDERR_EMPTY=ON
        -P ${PROJECT_SOURCE_DIR}/firmware/host/tests/run_cli.cmake)
set_tests_properties(cli_version PROPERTIES LABELS cli TIMEOUT 30)
