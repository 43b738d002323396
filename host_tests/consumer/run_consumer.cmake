# run_consumer.cmake - one consumer test (consumer_tests.cmake): builds the
# project in this directory against lmsego and checks what it gives.
#
#   cmake -DMODE=install|subdir -DLMSEGO_SOURCE_DIR=<repo> -DWORK=<scratch dir>
#         -DGENERATOR=<cmake generator> -DVERSION=<lmsego's version>
#         (-DC_COMPILER=<host cc> [-DPKG_CONFIG=<pkg-config>]
#          | -DTOOLCHAIN=<toolchain file> -DNM=<arm-none-eabi-nm>)
#         -P run_consumer.cmake
#
# install: lmsego alone (libraries only) is configured, built and installed
#   to WORK/prefix with `cmake --install --prefix` (not its configured
#   prefix: the package and lmsego.pc must be relocatable), the install
#   tree is checked, then the consumer uses find_package(lmsego); on the
#   host also pkg-config, whose flags build the consumer once more.
# subdir: the consumer does add_subdirectory(LMSEGO_SOURCE_DIR) (its own
#   CMakeLists.txt checks that it got the libraries only).
# Host consumers run and must print the expected line; Cortex-M consumers
# are linked and must contain the lmsego functions they call.
cmake_minimum_required(VERSION 3.21)
foreach(var MODE LMSEGO_SOURCE_DIR WORK GENERATOR VERSION)
    if(NOT DEFINED ${var})
        message(FATAL_ERROR "run_consumer.cmake: ${var} is not set")
    endif()
endforeach()
set(consumer_dir ${CMAKE_CURRENT_LIST_DIR})

# run(COMMAND...): runs it, fails the test with its output on an error;
# its stdout in run_out.
function(run)
    execute_process(COMMAND ${ARGN} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
    if(NOT rc EQUAL 0)
        string(REPLACE ";" " " cmd "${ARGN}")
        message(FATAL_ERROR "failed (${rc}): ${cmd}\n${out}${err}")
    endif()
    set(run_out "${out}" PARENT_SCOPE)
endfunction()

# check_output(TEXT): the host consumer's line.
string(REPLACE "." "\\." version_re "${VERSION}")
set(expected_re
    "^lmsego ${version_re} crc=a656 sqrt=1000000 sin90=1073741824 cos90=0 bytes=372 scans=1 lines=0\n$")
function(check_output text what)
    if(NOT text MATCHES "${expected_re}")
        message(FATAL_ERROR "${what} printed '${text}', expected /${expected_re}/")
    endif()
    message(STATUS "${what}: ${text}")
endfunction()

file(REMOVE_RECURSE ${WORK})
set(common -G ${GENERATOR})
if(DEFINED TOOLCHAIN)
    list(APPEND common -DCMAKE_TOOLCHAIN_FILE=${TOOLCHAIN})
else()
    list(APPEND common -DCMAKE_C_COMPILER=${C_COMPILER})
endif()

if(MODE STREQUAL "install")
    set(prefix ${WORK}/prefix)
    run(${CMAKE_COMMAND} -S ${LMSEGO_SOURCE_DIR} -B ${WORK}/lmsego ${common}
        -DLMSEGO_BUILD_TESTS=OFF -DLMSEGO_BUILD_TOOLS=OFF -DLMSEGO_BUILD_IMAGES=OFF
        -DCMAKE_INSTALL_PREFIX=${WORK}/not-here)
    run(${CMAKE_COMMAND} --build ${WORK}/lmsego -j 2)
    run(${CMAKE_COMMAND} --install ${WORK}/lmsego --prefix ${prefix})
    # What must be there, and what must not (host-only and board headers).
    foreach(file include/lmsego/ego_loop.h include/lmsego/ego_fx_math.h include/lmsego/lms_crc.h
            include/lmsego/lms_sim.h include/lmsego/lmsego_version.h
            lib/liblms_driver.a lib/liblms_estimator.a lib/libego_firmware.a lib/liblms_sim.a
            lib/cmake/lmsego/lmsegoConfig.cmake lib/cmake/lmsego/lmsegoConfigVersion.cmake
            lib/pkgconfig/lmsego.pc)
        if(NOT EXISTS ${prefix}/${file})
            message(FATAL_ERROR "not installed: ${file}")
        endif()
    endforeach()
    foreach(file include/lmsego/lms_serial.h include/lmsego/cli.h include/lmsego/hal_mps2.h
            include/lmsego/posix include/lmsego/host include/lmsego/target include/lmsego/sim
            bin/lmsego)
        if(EXISTS ${prefix}/${file})
            message(FATAL_ERROR "installed but should not be: ${file}")
        endif()
    endforeach()
    set(consumer_args -DCMAKE_PREFIX_PATH=${prefix})
elseif(MODE STREQUAL "subdir")
    set(consumer_args -DLMSEGO_SOURCE_DIR=${LMSEGO_SOURCE_DIR})
else()
    message(FATAL_ERROR "run_consumer.cmake: MODE must be install or subdir, not '${MODE}'")
endif()

run(${CMAKE_COMMAND} -S ${consumer_dir} -B ${WORK}/consumer ${common} ${consumer_args})
run(${CMAKE_COMMAND} --build ${WORK}/consumer -j 2)

if(DEFINED TOOLCHAIN)
    set(elf ${WORK}/consumer/consumer)
    if(NOT EXISTS ${elf})
        set(elf ${WORK}/consumer/consumer.elf)
    endif()
    run(${NM} --defined-only ${elf})
    foreach(symbol lms_crc16 fx_sqrt_u64 fx_sincos ego_loop_init ego_loop_step)
        if(NOT run_out MATCHES " T ${symbol}\n")
            message(FATAL_ERROR "${symbol} is not in the Cortex-M consumer ${elf}")
        endif()
    endforeach()
    message(STATUS "Cortex-M consumer linked: ${elf}")
    return()
endif()

run(${WORK}/consumer/consumer)
check_output("${run_out}" "consumer (${MODE})")

if(NOT MODE STREQUAL "install")
    return()
endif()
# pkg-config: its flags must build the consumer by hand; without
# pkg-config on the machine, the file's content is checked instead.
set(pc_file ${prefix}/lib/pkgconfig/lmsego.pc)
if(PKG_CONFIG)
    set(ENV{PKG_CONFIG_PATH} ${prefix}/lib/pkgconfig)
    run(${PKG_CONFIG} --modversion lmsego)
    if(NOT run_out STREQUAL "${VERSION}\n")
        message(FATAL_ERROR "pkg-config --modversion lmsego: '${run_out}', expected ${VERSION}")
    endif()
    run(${PKG_CONFIG} --cflags --libs lmsego)
    string(STRIP "${run_out}" pc_flags)
    # The include directory, the definitions that size the public structs
    # as the libraries were built (EGO_LOOP_OBJECTS, EGO_MAX_BEAMS when
    # set), the libraries.
    if(NOT pc_flags MATCHES "^-I[^ ]*/include/lmsego +-DEGO_LOOP_OBJECTS=[01]( +-DEGO_MAX_BEAMS=[0-9]+u)? +-L[^ ]*/lib +-lego_firmware -llms_estimator -llms_driver$")
        message(FATAL_ERROR "pkg-config --cflags --libs lmsego: '${pc_flags}'")
    endif()
    separate_arguments(pc_args UNIX_COMMAND "${pc_flags}")
    run(${C_COMPILER} -std=c11 -Wall -Wextra -Werror -DCONSUMER_HOST ${consumer_dir}/consumer.c ${pc_args}
        -o ${WORK}/consumer_pc)
    run(${WORK}/consumer_pc)
    check_output("${run_out}" "consumer (pkg-config)")
else()
    file(READ ${pc_file} pc)
    foreach(re "\nVersion: ${version_re}\n" "\nLibs: -L\\\${libdir} -lego_firmware -llms_estimator -llms_driver\n"
            "\nCflags: -I\\\${includedir}/lmsego -DEGO_LOOP_OBJECTS=[01]( -DEGO_MAX_BEAMS=[0-9]+u)?\n")
        if(NOT pc MATCHES "${re}")
            message(FATAL_ERROR "${pc_file} does not match /${re}/:\n${pc}")
        endif()
    endforeach()
    message(STATUS "pkg-config not found: ${pc_file} checked as text")
endif()
