/* target.h - the board layer of the Cortex-M images (MPS2 boards under
 * QEMU: AN385 Cortex-M3, AN386 Cortex-M4F): startup (startup.c), the
 * CMSDK UART0 and the SysTick instruction counter (hal_mps2.c), and the
 * semihosting exit that ends a run with an exit code QEMU passes on.
 *
 * No vendor code: the register addresses are the board's (see
 * ../shared/guides/cortex-m-target.md and docs/firmware.md).
 */
#ifndef LMSEGO_TARGET_H
#define LMSEGO_TARGET_H

#include <stddef.h>
#include <stdint.h>

/* Exit codes of a run (QEMU's own exit status). */
#define TARGET_EXIT_OK 0
#define TARGET_EXIT_FAILED 1        /* the image's own check failed */
/* Unit-test images (unit/unit_exit.c): 1..119 failed tests (more are
 * reported as 119), 120 the test harness was misused (a TEST_ macro
 * outside RUN_TEST). */
#define TARGET_EXIT_TESTS_FAILED_MAX 119
#define TARGET_EXIT_ABORTED 120
#define TARGET_EXIT_HARDFAULT 121
#define TARGET_EXIT_MEMMANAGE 122
#define TARGET_EXIT_BUSFAULT 123
#define TARGET_EXIT_USAGEFAULT 124
#define TARGET_EXIT_NMI 125
#define TARGET_EXIT_UNEXPECTED 126  /* any other exception */
#define TARGET_EXIT_RETURNED 127    /* main returned without exiting */

/* Ends the run: semihosting SYS_EXIT_EXTENDED, QEMU exits with code. */
_Noreturn void target_exit(int code);

/* startup.c calls main(0, {NULL}) (argc 0, like a program started without
 * a name; main(void) works as well) and ends the run with
 * target_exit(target_main_exit_code(main's return value)). The default
 * (weak, startup.c) is the product images' rule: they end with target_exit
 * themselves, so a return is flagged as TARGET_EXIT_RETURNED, except a
 * nonzero value, which is passed on. Unit-test images link unit/unit_exit.c,
 * whose definition makes the return value (UNITY_END(), the number of
 * failed tests) the exit code, so 0 is success. */
int target_main_exit_code(int main_returned);

/* UART0: transmitter on (115200 8N1 on a real board; QEMU ignores the
 * divider). */
void target_uart_init(void);
/* Writes len bytes, waiting while the transmit buffer is full. */
void target_uart_write(const uint8_t *bytes, size_t len);
/* A NUL-terminated text. */
void target_uart_puts(const char *text);
/* One character, given as putchar takes it (the low 8 bits are sent): the
 * output hook of the unit-test images (unit/unity_config.h). */
void target_uart_putc(int c);

/* SysTick as a free-running counter of the core clock (25 MHz on MPS2),
 * with an interrupt counting its 2^24 wraps. Under QEMU with
 * -icount shift=0 (one instruction per nanosecond) one tick is exactly 40
 * instructions, so target_instructions() counts instructions, the same
 * run after run (to 40). */
#define TARGET_INSNS_PER_TICK 40u /* 10^9 instructions/s (icount) / 25 MHz */
void target_clock_init(void);
uint64_t target_instructions(void);
/* The same, but the SysTick interrupt comes every `ticks` ticks (2 ..
 * 2^24) and calls target_tick() each time: a periodic interrupt for the
 * image's own work (weak default: nothing). */
void target_clock_init_period(uint32_t ticks);
void target_tick(void);

/* Built with TARGET_PC_SAMPLING (a profiling build: docs/firmware.md),
 * SysTick also samples the interrupted program counter every 39 880
 * instructions into TARGET_PC_BUCKETS counters of TARGET_PC_BUCKET_BYTES
 * of flash each (the first 256 KiB). */
#define TARGET_PC_BUCKET_BYTES 64u
#define TARGET_PC_BUCKETS 4096u
#if defined(TARGET_PC_SAMPLING)
const uint32_t *target_pc_samples(void);
#endif

/* Stack high-water mark: the bytes of the stack ever used since reset
 * (startup.c paints the stack before main). */
uint32_t target_stack_used(void);
uint32_t target_stack_size(void);

#endif /* LMSEGO_TARGET_H */
