/* fx_math.h - integer trigonometry and square root of the estimator.
 *
 * The project's own routines (no libm): same bits on the host and on a
 * Cortex-M. Each one is tested over its whole input range against a
 * double-precision oracle (host_tests/unit/test_fx_math.c); the worst
 * errors, in LSB and in physical units, are in docs/fixed-point.md.
 * Pure functions, reentrant, bounded time; tables are static const (flash).
 */
#ifndef FX_MATH_H
#define FX_MATH_H

#include <stdint.h>

#include "fx.h"

/* sin and cos of a binary angle, Q2.30 (1.0 = 0x40000000, exactly reached
 * at 0, 90, 180, 270 deg). Both outputs must be non-NULL. */
void fx_sincos(fx_bam32_t angle, fx_q2_30_t *sin_out, fx_q2_30_t *cos_out);
fx_q2_30_t fx_sin(fx_bam32_t angle);
fx_q2_30_t fx_cos(fx_bam32_t angle);

/* atan2(y, x) as a binary angle in [0, 1 turn): y and x in any common
 * scale, the whole int64 range allowed (INT64_MIN included).
 * fx_atan2(0, 0) is 0. */
fx_bam32_t fx_atan2(int64_t y, int64_t x);

/* Square root of v, rounded to the nearest integer (a result of 2^32 - 1
 * for the top of the range, where the rounded root would not fit). Used on
 * sums of squares: sqrt of a Q32.32 value is its Q16.16 root. */
uint32_t fx_sqrt_u64(uint64_t v);

#endif /* FX_MATH_H */
