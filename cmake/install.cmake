# Install rules (LMSEGO_INSTALL, on by default when lmsego is the top-level
# project; docs/install.md):
#   lib/                 liblms_driver.a liblms_estimator.a libego_firmware.a liblms_sim.a
#   include/lmsego/      the public headers of driver/, driver/sim/, estimator/,
#                        firmware/ (flat) and the generated lmsego_version.h
#   lib/cmake/lmsego/    the CMake package: lmsego::driver, ::estimator,
#                        ::firmware, ::sim
#   lib/pkgconfig/       lmsego.pc
#   bin/lmsego           the command-line program (host builds with tools)
include(CMakePackageConfigHelpers)

set(LMSEGO_CMAKE_INSTALL_DIR ${CMAKE_INSTALL_LIBDIR}/cmake/lmsego)
set(LMSEGO_INCLUDE_INSTALL_DIR ${CMAKE_INSTALL_INCLUDEDIR}/lmsego)

# The names users write, the same as the in-tree ALIAS targets.
set_target_properties(lms_driver PROPERTIES EXPORT_NAME driver)
set_target_properties(lms_estimator PROPERTIES EXPORT_NAME estimator)
set_target_properties(ego_firmware PROPERTIES EXPORT_NAME firmware)
set_target_properties(lms_sim PROPERTIES EXPORT_NAME sim)

# lmsego_warnings: see cmake/warnings.cmake (empty once installed).
install(TARGETS lms_driver lms_estimator ego_firmware lms_sim lmsego_warnings
    EXPORT lmsegoTargets
    ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR})

# Headers, flat: the host-only ones (driver/posix, firmware/host) and the
# board files (firmware/target) stay behind. driver/sim/ has its own rule
# (an EXCLUDE of "sim" would match it whole).
install(DIRECTORY ${PROJECT_SOURCE_DIR}/driver/ ${PROJECT_SOURCE_DIR}/estimator/
    ${PROJECT_SOURCE_DIR}/firmware/
    DESTINATION ${LMSEGO_INCLUDE_INSTALL_DIR}
    FILES_MATCHING PATTERN "*.h"
    PATTERN "posix" EXCLUDE
    PATTERN "sim" EXCLUDE
    PATTERN "host" EXCLUDE
    PATTERN "target" EXCLUDE)
install(DIRECTORY ${PROJECT_SOURCE_DIR}/driver/sim/
    DESTINATION ${LMSEGO_INCLUDE_INSTALL_DIR}
    FILES_MATCHING PATTERN "*.h")
install(FILES ${LMSEGO_GENERATED_INCLUDE_DIR}/lmsego_version.h
    DESTINATION ${LMSEGO_INCLUDE_INSTALL_DIR})

# The CMake package, relocatable (paths relative to its own location).
install(EXPORT lmsegoTargets
    NAMESPACE lmsego::
    DESTINATION ${LMSEGO_CMAKE_INSTALL_DIR})
configure_package_config_file(${PROJECT_SOURCE_DIR}/cmake/lmsegoConfig.cmake.in
    ${PROJECT_BINARY_DIR}/lmsegoConfig.cmake
    INSTALL_DESTINATION ${LMSEGO_CMAKE_INSTALL_DIR})
# SameMinorVersion: before 1.0 a minor release may break the API (0.2.0
# changes the estimator's), so find_package(lmsego 0.2) takes 0.2.x only.
write_basic_package_version_file(${PROJECT_BINARY_DIR}/lmsegoConfigVersion.cmake
    COMPATIBILITY SameMinorVersion)
install(FILES ${PROJECT_BINARY_DIR}/lmsegoConfig.cmake
    ${PROJECT_BINARY_DIR}/lmsegoConfigVersion.cmake
    DESTINATION ${LMSEGO_CMAKE_INSTALL_DIR})

# lmsego.pc, relocatable too: its prefix is found from the file's own
# directory (${pcfiledir}), so `cmake --install --prefix P` gives a right
# file for any P; absolute install directories are written as they are.
if(IS_ABSOLUTE "${CMAKE_INSTALL_LIBDIR}" OR IS_ABSOLUTE "${CMAKE_INSTALL_INCLUDEDIR}")
    set(LMSEGO_PC_PREFIX ${CMAKE_INSTALL_PREFIX})
    set(LMSEGO_PC_LIBDIR ${CMAKE_INSTALL_FULL_LIBDIR})
    set(LMSEGO_PC_INCLUDEDIR ${CMAKE_INSTALL_FULL_INCLUDEDIR})
else()
    file(RELATIVE_PATH up /p/${CMAKE_INSTALL_LIBDIR}/pkgconfig /p)
    string(REGEX REPLACE "/$" "" up "${up}")
    set(LMSEGO_PC_PREFIX "\${pcfiledir}/${up}")
    set(LMSEGO_PC_LIBDIR "\${prefix}/${CMAKE_INSTALL_LIBDIR}")
    set(LMSEGO_PC_INCLUDEDIR "\${prefix}/${CMAKE_INSTALL_INCLUDEDIR}")
endif()
# The definitions that size the public structs, as the libraries were
# built (the CMake package carries them on its targets).
if(LMSEGO_LOOP_OBJECTS)
    set(LMSEGO_PC_DEFINES "-DEGO_LOOP_OBJECTS=1")
else()
    set(LMSEGO_PC_DEFINES "-DEGO_LOOP_OBJECTS=0")
endif()
if(LMSEGO_MAX_BEAMS)
    string(APPEND LMSEGO_PC_DEFINES " -DEGO_MAX_BEAMS=${LMSEGO_MAX_BEAMS}u")
endif()
configure_file(${PROJECT_SOURCE_DIR}/cmake/lmsego.pc.in ${PROJECT_BINARY_DIR}/lmsego.pc @ONLY)
install(FILES ${PROJECT_BINARY_DIR}/lmsego.pc DESTINATION ${CMAKE_INSTALL_LIBDIR}/pkgconfig)

if(TARGET lmsego)
    install(TARGETS lmsego RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
endif()
