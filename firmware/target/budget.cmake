# budget.cmake: memory budgets of the firmware loop, from an image.
#   -DSIZE=arm-none-eabi-size -DNM=arm-none-eabi-nm -DIMAGE=<elf>
#   -DSU_DIR=<build dir with the -fstack-usage .su files> -DOUT=<report file>
#   [-DCHECK=ON]
#   [-DMAP=<the image's map file> -DEXCLUDE_SOURCES=<regex>
#    -DEXCLUDE_SYMBOLS=<regex>]
# Flash of the loop = .isr_vector + .text + .ARM.exidx + .data, RAM =
# .data + .bss, less what is not the firmware's:
# - without MAP (the replay images): the embedded test stream
#   (lmsego_stream) from the flash and the image's own measurement buffer
#   (insns) from the RAM, shown apart;
# - with MAP (the session image, whose simulated scanner is scaffolding
#   too): every input section of the map that comes from an object file
#   compiled from a source matching EXCLUDE_SOURCES (a regex for the whole
#   file name, e.g. "lms_sim[.]c|session_scene_stream[.]c"), or whose
#   symbol matches EXCLUDE_SYMBOLS (the whole name, e.g.
#   "sim_[A-Za-z0-9_]*|insns"; the symbol of .text.NAME, .bss.NAME, ...;
#   a suffix such as .constprop.0 is ignored),
#   from flash (.text, .rodata, .ARM.exidx; .data's initial values) and
#   RAM (.data, .bss). Needs -ffunction-sections -fdata-sections (the
#   toolchain file sets them), else a file's sections are not per symbol.
# Stack: the largest single frame from -fstack-usage (with MAP: only the
# files linked into the image, not the excluded ones); the worst case
# through the call graph is measured by the images ('# stack_bytes used='
# lines). With CHECK, fails above FLASH_LIMIT bytes of flash (default 64
# KiB) or 32 KiB RAM (the limits of issue 6).
execute_process(COMMAND ${SIZE} -A ${IMAGE} OUTPUT_VARIABLE sections RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
    message(FATAL_ERROR "${SIZE} failed on ${IMAGE}")
endif()
function(section_size name var)
    if(sections MATCHES "\n\\${name}[ ]+([0-9]+)")
        set(${var} ${CMAKE_MATCH_1} PARENT_SCOPE)
    else()
        set(${var} 0 PARENT_SCOPE)
    endif()
endfunction()
section_size(.isr_vector vec)
section_size(.text text)
section_size(.ARM.exidx exidx)
section_size(.data data)
section_size(.bss bss)
section_size(.stack stack)
execute_process(COMMAND ${NM} -S ${IMAGE} OUTPUT_VARIABLE symbols)
function(symbol_size name var)
    if(symbols MATCHES "[0-9a-f]+ ([0-9a-f]+) [A-Za-z] ${name}\n")
        math(EXPR v "0x${CMAKE_MATCH_1}")
        set(${var} ${v} PARENT_SCOPE)
    else()
        set(${var} 0 PARENT_SCOPE)
    endif()
endfunction()
# True (in var) when a symbol is one of EXCLUDE_SYMBOLS.
function(symbol_excluded sym var)
    string(REGEX REPLACE "[.].*$" "" sym "${sym}") # foo.constprop.0 -> foo
    if(NOT EXCLUDE_SYMBOLS STREQUAL "" AND sym MATCHES "^(${EXCLUDE_SYMBOLS})$")
        set(${var} TRUE PARENT_SCOPE)
    else()
        set(${var} FALSE PARENT_SCOPE)
    endif()
endfunction()

if(MAP)
    # Input sections: " .kind.name  0xADDRESS  0xSIZE  object", the name
    # alone on its line when it is long. Only the memory map part (the
    # discarded sections are listed before it).
    file(READ "${MAP}" map)
    string(FIND "${map}" "Linker script and memory map" at)
    if(at LESS 0)
        message(FATAL_ERROR "${MAP}: no memory map")
    endif()
    string(SUBSTRING "${map}" ${at} -1 map)
    string(REPLACE ";" "," map "${map}")
    string(REGEX MATCHALL "\n [.][^ \n]+[ \n]+0x[0-9a-f]+[ ]+0x[0-9a-f]+ [^\n]+" entries "${map}")
    set(excl_flash 0)
    set(excl_data 0)
    set(excl_bss 0)
    set(objects "")
    foreach(e IN LISTS entries)
        if(NOT e MATCHES "^\n ([.][^ \n]+)[ \n]+0x[0-9a-f]+[ ]+0x([0-9a-f]+) (.+)$")
            continue()
        endif()
        set(name "${CMAKE_MATCH_1}")
        math(EXPR size "0x${CMAKE_MATCH_2}")
        # "lib.a(file.c.obj)" or "CMakeFiles/x.dir/file.c.obj": file.c
        string(REGEX REPLACE "^.*[/(]" "" src "${CMAKE_MATCH_3}")
        string(REGEX REPLACE "[.]o(bj)?[)]?$" "" src "${src}")
        list(APPEND objects "${src}")
        if(name MATCHES "^[.](text|rodata|ARM[.]exidx)")
            set(kind flash)
        elseif(name MATCHES "^[.]data")
            set(kind data)
        elseif(name MATCHES "^[.]bss")
            set(kind bss)
        else()
            continue() # .ARM.attributes, .comment: not in the image's memory
        endif()
        string(REGEX REPLACE "^[.]ARM[.]exidx" "" sym "${name}")
        string(REGEX REPLACE "^[.](text|rodata|data|bss)[.]" "" sym "${sym}")
        symbol_excluded("${sym}" by_symbol)
        if(by_symbol OR (NOT EXCLUDE_SOURCES STREQUAL "" AND src MATCHES "^(${EXCLUDE_SOURCES})$"))
            math(EXPR excl_${kind} "${excl_${kind}} + ${size}")
        endif()
    endforeach()
    list(REMOVE_DUPLICATES objects)
    math(EXPR flash "${vec} + ${text} + ${exidx} + ${data} - ${excl_flash} - ${excl_data}")
    math(EXPR ram "${data} + ${bss} - ${excl_data} - ${excl_bss}")
    math(EXPR flash_excluded "${excl_flash} + ${excl_data}")
    math(EXPR ram_excluded "${excl_data} + ${excl_bss}")
else()
    symbol_size(lmsego_stream stream)
    symbol_size(insns measure)
    math(EXPR flash "${vec} + ${text} + ${exidx} + ${data} - ${stream}")
    math(EXPR ram "${data} + ${bss} - ${measure}")
endif()
# The largest frame of any function (lines "file:line:col:fn<TAB>bytes<TAB>kind").
file(GLOB_RECURSE su_files "${SU_DIR}/*.su")
set(frame_max 0)
set(frame_fn "")
foreach(f IN LISTS su_files)
    if(MAP)
        # Only the files linked into the image, and not the excluded ones.
        get_filename_component(src "${f}" NAME)
        string(REGEX REPLACE "[.]su$" "" src "${src}")
        list(FIND objects "${src}" linked)
        if(linked LESS 0 OR
           (NOT EXCLUDE_SOURCES STREQUAL "" AND src MATCHES "^(${EXCLUDE_SOURCES})$"))
            continue()
        endif()
    endif()
    file(STRINGS ${f} lines)
    foreach(line IN LISTS lines)
        if(line MATCHES ":([A-Za-z_0-9.]+)\t([0-9]+)\t")
            set(fn "${CMAKE_MATCH_1}")
            set(bytes "${CMAKE_MATCH_2}")
            if(MAP)
                symbol_excluded("${fn}" by_symbol)
                if(by_symbol)
                    continue()
                endif()
            endif()
            if(bytes GREATER frame_max)
                set(frame_max ${bytes})
                set(frame_fn ${fn})
            endif()
        endif()
    endforeach()
endforeach()
if(MAP)
    set(report "flash_loop=${flash} ram_loop=${ram} flash_excluded=${flash_excluded} ram_excluded=${ram_excluded} stack_section=${stack} largest_frame=${frame_max} (${frame_fn})")
else()
    set(report "flash_loop=${flash} ram_loop=${ram} ram_measurement=${measure} stack_section=${stack} largest_frame=${frame_max} (${frame_fn}) stream_in_flash=${stream}")
endif()
file(WRITE "${OUT}" "${report}\n")
message(STATUS "lmsego firmware budget: ${report}")
if(CHECK)
    if(NOT DEFINED FLASH_LIMIT)
        set(FLASH_LIMIT 65536)
    endif()
    if(flash GREATER FLASH_LIMIT)
        message(FATAL_ERROR "flash of the loop ${flash} B > ${FLASH_LIMIT} B")
    endif()
    if(ram GREATER 32768)
        message(FATAL_ERROR "RAM of the loop ${ram} B > 32 KiB")
    endif()
endif()
