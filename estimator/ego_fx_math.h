/* ego_fx_math.h - integer trigonometry and square root of the estimator.
 *
 * The project's own routines (no libm): same bits on the host and on a
 * Cortex-M. Each one is tested over its whole input range against a host
 * reference (host_tests/unit/test_fx_math.c: long double sinl/cosl/atan2l,
 * integer arithmetic for the root); the worst errors, in LSB and in
 * physical units, are in docs/fixed-point.md. Pure functions, reentrant,
 * bounded time, no 64-bit division; tables are static const (flash,
 * 3076 bytes in ego_fx_math_tables.h).
 */
#ifndef FX_MATH_H
#define FX_MATH_H

#include <stdint.h>

#include "ego_fx.h"

/* sin and cos of a binary angle, Q2.30 (1.0 = 0x40000000, exactly reached
 * at 0, 90, 180, 270 deg). Both outputs must be non-NULL.
 * Measured over all 2^32 angles: worst error 0.7525 LSB (7.0e-10); exact
 * symmetries sin(-a) == -sin(a), sin(a + half) == -sin(a),
 * cos(a) == sin(a + quarter); sin non-decreasing and cos non-increasing on
 * [0, 90] deg. fx_sin and fx_cos return exactly fx_sincos's outputs. */
void fx_sincos(fx_bam32_t angle, fx_q2_30_t *sin_out, fx_q2_30_t *cos_out);
fx_q2_30_t fx_sin(fx_bam32_t angle);
fx_q2_30_t fx_cos(fx_bam32_t angle);

/* atan2(y, x) as a binary angle in [0, 1 turn): y and x in any common
 * scale, the whole int64 range allowed (INT64_MIN included).
 * fx_atan2(0, 0) is 0. Axes and diagonals are exact (multiples of 1/8
 * turn); atan2(-y, x) == -atan2(y, x), atan2(y, -x) == half - atan2(y, x),
 * atan2(x, y) == quarter - atan2(y, x), scaling both by 2^k changes
 * nothing. Worst error measured 0.8433 LSB (1.2e-9 rad, on 2^26 random
 * pairs; error bound 0.92 LSB). */
fx_bam32_t fx_atan2(int64_t y, int64_t x);

/* atan2(y, x) within FX_ATAN2_QUICK_ERROR of fx_atan2's: for a search
 * whose answer only needs a start near the right place (ITCP's walk,
 * tracking's association). The octant as fx_atan2; the ratio in Q16 by
 * one 32-bit division after both are cut to 16 significant bits, and
 * atan interpolated in a table of 32nds. The error: 2^18, 0.022 deg
 * (the parts add up to 1.6e-4 rad; measured against fx_atan2 over 2e7
 * random vectors of every magnitude: at most 75 655, 1.1e-4 rad). */
#define FX_ATAN2_QUICK_ERROR 262144
fx_bam32_t fx_atan2_quick(int64_t y, int64_t x);

/* Significant bits of d (d != 0: 1 .. 32). */
unsigned fx_bits_u32(uint32_t d);

/* Square root of v, rounded to the nearest integer (a result of 2^32 - 1
 * for the top of the range, v > 2^64 - 2^32, where the rounded root would
 * not fit). Used on sums of squares: sqrt of a Q32.32 value is its Q16.16
 * root. Exact (checked for every v < 2^32 and every k^2 - 1, k^2, k^2 + 1,
 * k^2 + k, k^2 + k + 1 with k < 2^32). */
uint32_t fx_sqrt_u64(uint64_t v);

#endif /* FX_MATH_H */
