/* live_common.h - what the live commands (run, record: cmd_run.c; sim,
 * play: cmd_sim.c) share: a monotonic clock, SIGINT / SIGTERM as a stop
 * request, and the rate and unit option values. Host-only.
 */
#ifndef LMSEGO_LIVE_COMMON_H
#define LMSEGO_LIVE_COMMON_H

#include <stdbool.h>
#include <stdint.h>

#include "lms_proto.h"

/* Microseconds of CLOCK_MONOTONIC. */
uint64_t live_monotonic_us(void);

/* From now on SIGINT and SIGTERM only set a flag (system calls they
 * interrupt return EINTR), and SIGPIPE is ignored. */
void live_catch_stop_signals(void);

/* True once SIGINT or SIGTERM came. */
bool live_stop_requested(void);

/* "9600", "19200", "38400", "500000"; "?" for anything else. */
const char *live_baud_name(lms_baud_t baud);

/* The inverse of live_baud_name; 0, or -1 for NULL or any other text. */
int live_parse_baud(const char *text, lms_baud_t *baud);

/* "cm" or "mm"; 0, or -1 for NULL or any other text. */
int live_parse_unit(const char *text, lms_unit_t *unit);

#endif /* LMSEGO_LIVE_COMMON_H */
