/* report.h - the '#' measurement lines that the target images write after
 * their output (UART0 through target.h; no stdio). */
#ifndef LMSEGO_REPORT_H
#define LMSEGO_REPORT_H

#include <stdint.h>

/* Writes name, then value in decimal ("# insns_per_scan median=" 123). */
void report_field(const char *name, uint64_t value);

/* The same for value / 10^decimals ("... per_byte=" 14.69 from 1469, 2). */
void report_fixed(const char *name, uint64_t value, unsigned decimals);

/* The median of v[0 .. n - 1] (the upper one for even n; 0 for n = 0).
 * Sorts v in place: an insertion sort, for the few hundred per-scan counts
 * an image keeps, once at the end of a run. */
uint32_t report_median(uint32_t *v, uint32_t n);

#endif /* LMSEGO_REPORT_H */
