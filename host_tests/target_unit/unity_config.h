/* unity_config.h - the test harness's output hooks on the Cortex-M
 * unit-test images (host_tests/unity/unity.h, "Output"), read by unity.h
 * when UNITY_INCLUDE_CONFIG_H is defined (CMakeLists.txt here). The results
 * go to UART0, which QEMU shows on its stdout; nothing of newlib's stdio is
 * used, so the heap guard (../heap_guard.c) holds for the test images too. */
#ifndef LMSEGO_UNITY_CONFIG_H
#define LMSEGO_UNITY_CONFIG_H

#include "target.h"

#define UNITY_OUTPUT_START() target_uart_init()
#define UNITY_OUTPUT_CHAR(c) target_uart_putc(c)
#define UNITY_OUTPUT_FLUSH() ((void)0)
/* A TEST_ macro outside RUN_TEST: the message is on the UART, then the run
 * ends with its own code. */
#define UNITY_OUTPUT_ABORT() target_exit(TARGET_EXIT_ABORTED)

#endif /* LMSEGO_UNITY_CONFIG_H */
