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

set(allowed_headers stdint.h stddef.h stdbool.h limits.h string.h)

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
if(failed GREATER 0)
    message(FATAL_ERROR "${failed} portable source(s) did not compile for Cortex-M3")
endif()
