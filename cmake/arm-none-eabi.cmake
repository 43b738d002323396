# Toolchain file: arm-none-eabi-gcc for the Cortex-M presets (see
# CMakePresets.json and docs/firmware.md). LMSEGO_CPU picks the core and the
# QEMU board that emulates it:
#   cortex-m3   -mcpu=cortex-m3, no FPU                  QEMU mps2-an385
#   cortex-m4f  -mcpu=cortex-m4, FPv4-SP, hard-float ABI QEMU mps2-an386
# Images run under QEMU through CMAKE_CROSSCOMPILING_EMULATOR, so ctest runs
# them like host programs; -icount shift=0 makes one instruction one virtual
# nanosecond, so the images' own SysTick readings count instructions.
set(CMAKE_SYSTEM_NAME Generic)
set(CMAKE_SYSTEM_PROCESSOR arm)
set(CMAKE_C_COMPILER arm-none-eabi-gcc)
# No _exit etc. for a test executable at configure time: test a library.
set(CMAKE_TRY_COMPILE_TARGET_TYPE STATIC_LIBRARY)

set(LMSEGO_CPU "cortex-m3" CACHE STRING "Target core: cortex-m3 or cortex-m4f")
set_property(CACHE LMSEGO_CPU PROPERTY STRINGS cortex-m3 cortex-m4f)
if(LMSEGO_CPU STREQUAL "cortex-m4f")
    set(LMSEGO_CPU_FLAGS "-mthumb -mcpu=cortex-m4 -mfpu=fpv4-sp-d16 -mfloat-abi=hard")
    set(LMSEGO_QEMU_MACHINE mps2-an386)
elseif(LMSEGO_CPU STREQUAL "cortex-m3")
    set(LMSEGO_CPU_FLAGS "-mthumb -mcpu=cortex-m3")
    set(LMSEGO_QEMU_MACHINE mps2-an385)
else()
    message(FATAL_ERROR "LMSEGO_CPU must be cortex-m3 or cortex-m4f, not '${LMSEGO_CPU}'")
endif()

# -fstack-usage writes each object's frames (.su); -fcallgraph-info=su writes
# its call graph with those frames (.ci, VCG text) for the worst-case stack
# through the call graph (firmware/target/stack_graph.py).
set(CMAKE_C_FLAGS_INIT
    "${LMSEGO_CPU_FLAGS} -ffunction-sections -fdata-sections -fstack-usage -fcallgraph-info=su")
# Our own startup code (no crt0), newlib-nano without system calls; the
# firmware uses no stdio, so nothing of newlib's heap is linked (the heap
# guard in firmware/target/heap_guard.c makes sure).
set(CMAKE_EXE_LINKER_FLAGS_INIT
    "${LMSEGO_CPU_FLAGS} -nostartfiles -specs=nano.specs -specs=nosys.specs -Wl,--gc-sections")
set(CMAKE_C_FLAGS_RELEASE_INIT "-O2 -DNDEBUG")
set(CMAKE_C_FLAGS_MINSIZEREL_INIT "-Os -DNDEBUG")

set(CMAKE_FIND_ROOT_PATH_MODE_PROGRAM NEVER)
find_program(LMSEGO_QEMU qemu-system-arm)
if(LMSEGO_QEMU)
    set(CMAKE_CROSSCOMPILING_EMULATOR
        ${LMSEGO_QEMU};-M;${LMSEGO_QEMU_MACHINE};-nographic;-monitor;none;-serial;stdio;-semihosting-config;enable=on,target=native;-icount;shift=0;-kernel)
endif()
