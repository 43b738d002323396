# cmake -P script: compile every file in SOURCES with CC for a Cortex-M3
# (only the cross compiler's own headers are on its path, never
# /usr/include), and allow only the freestanding C headers plus <string.h>
# in the portable core, so a stray <stdio.h> or POSIX header fails here even
# though newlib would provide one.
cmake_minimum_required(VERSION 3.21)

foreach(var CC SOURCES INCLUDE_DIRS OUT_DIR)
    if(NOT DEFINED ${var})
        message(FATAL_ERROR "compile_portable.cmake: ${var} is not set")
    endif()
endforeach()
file(MAKE_DIRECTORY ${OUT_DIR})

set(flags -std=c11 -mcpu=cortex-m3 -mthumb -Os -ffreestanding
    -Wall -Wextra -Wpedantic -Werror -Wconversion -Wsign-conversion -Wshadow
    -Wmissing-prototypes -Wstrict-prototypes -Wundef -Wvla -Wcast-qual
    -ffunction-sections -fdata-sections)
set(incs "")
foreach(dir IN LISTS INCLUDE_DIRS)
    list(APPEND incs -I${dir})
endforeach()

# <stdatomic.h> too: a compiler header like the freestanding ones (no libc
# behind it), for the firmware core's interrupt-to-main-loop mailbox; the
# check below makes sure its operations compile to instructions (LDREX /
# STREX on Cortex-M3) and not to calls into a libatomic a bare part lacks.
set(allowed_headers stdint.h stddef.h stdbool.h limits.h string.h stdatomic.h)

set(headers "")
foreach(dir IN LISTS INCLUDE_DIRS)
    file(GLOB dir_headers ${dir}/*.h)
    list(APPEND headers ${dir_headers})
endforeach()

list(REMOVE_ITEM SOURCES "")
set(failed 0)
foreach(src IN LISTS SOURCES headers)
    file(STRINGS "${src}" includes REGEX "^[ \t]*#[ \t]*include[ \t]*<")
    foreach(line IN LISTS includes)
        string(REGEX REPLACE "^[^<]*<([^>]*)>.*$" "\\1" header "${line}")
        if(NOT header IN_LIST allowed_headers)
            message("FAIL ${src}: <${header}> is not allowed in portable code")
            math(EXPR failed "${failed} + 1")
        endif()
    endforeach()
endforeach()

foreach(src IN LISTS SOURCES)
    get_filename_component(name ${src} NAME_WE)
    execute_process(
        COMMAND ${CC} ${flags} ${incs} -c ${src} -o ${OUT_DIR}/${name}.o
        RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
    if(NOT rc EQUAL 0)
        message("FAIL ${src}\n${out}${err}")
        math(EXPR failed "${failed} + 1")
    else()
        message("ok   ${src}")
    endif()
endforeach()
# No floating point may reach the portable code (the estimator must give the
# same bits on every target): an object that calls a soft-float helper
# (__aeabi_d*, __aeabi_f*, __aeabi_*2d, ...) on this FPU-less core fails.
get_filename_component(cc_dir ${CC} DIRECTORY)
find_program(NM NAMES arm-none-eabi-nm HINTS ${cc_dir})
if(NOT NM)
    message("FAIL arm-none-eabi-nm not found: cannot check for floating point")
    math(EXPR failed "${failed} + 1")
else()
    foreach(src IN LISTS SOURCES)
        get_filename_component(name ${src} NAME_WE)
        if(NOT EXISTS ${OUT_DIR}/${name}.o)
            continue()
        endif()
        execute_process(COMMAND ${NM} -u ${OUT_DIR}/${name}.o OUTPUT_VARIABLE undefined)
        string(REGEX MATCHALL "__aeabi_(d|f)[a-z0-9]+|__aeabi_[a-z0-9]+2(d|f)|__aeabi_(d|f)2[a-z0-9]+" soft_float "${undefined}")
        if(soft_float)
            message("FAIL ${src}: floating point on the target (${soft_float})")
            math(EXPR failed "${failed} + 1")
        endif()
        string(REGEX MATCHALL "__atomic_[a-z_0-9]+|__sync_[a-z_0-9]+" atomic_calls "${undefined}")
        if(atomic_calls)
            message("FAIL ${src}: atomic operations as library calls (${atomic_calls})")
            math(EXPR failed "${failed} + 1")
        endif()
    endforeach()
endif()

if(failed GREATER 0)
    message(FATAL_ERROR "${failed} portability check(s) failed for Cortex-M3")
endif()
