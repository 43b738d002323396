/* ego_fx.h - fixed-point types and helpers of the estimator.
 *
 * Convention (CMSIS-DSP's): Qm.n has m integer bits including the sign and
 * n fraction bits. The format is in every type name; docs/fixed-point.md
 * lists ranges, rounding and the error of every kernel.
 *
 *   fx_q16_16_t  int32   positions and lengths in metres; LSB 15.3 um, range
 *                        +-32768 m (the LMS reaches 81.9 m; a vehicle path is
 *                        kept relative, scan to scan)
 *   fx_q2_30_t   int32   sin/cos, unit vectors, weights in [-2, 2); LSB 9.3e-10
 *   fx_bam32_t   uint32  binary angle: 2^32 = one turn, LSB 1.46e-9 rad;
 *                        wraps for free in unsigned arithmetic
 *   int64_t              accumulators of products over a whole scan
 *
 * Defaults: every narrowing rounds to nearest (ties away from zero) and
 * saturates to the target type; cheaper variants say so in their name
 * (_wrap, _trunc). Signed overflow never happens: products are formed in
 * 64 bits, and shifts of negative values go through fx_shr_round_s64.
 * No float or double anywhere in estimator/ (host code converts in
 * host_tests/ and firmware/host/).
 */
#ifndef FX_H
#define FX_H

#include <stdint.h>

typedef int32_t fx_q16_16_t;
typedef int32_t fx_q2_30_t;
typedef uint32_t fx_bam32_t;

#define FX_Q16_16_ONE ((fx_q16_16_t)0x00010000)
#define FX_Q2_30_ONE ((fx_q2_30_t)0x40000000)

/* Binary angles of common fractions of a turn. */
#define FX_BAM32_QUARTER 0x40000000u /* 90 deg */
#define FX_BAM32_HALF 0x80000000u    /* 180 deg */

/* Metres (literal, may be fractional) to Q16.16, rounded: for constants
 * only; the argument is evaluated more than once and must be a literal.
 * The result is an arithmetic constant expression that the compiler folds
 * to an integer (no floating point reaches the target code: the Cortex-M
 * portability check would fail on a soft-float call), usable in
 * initializers and code but not in _Static_assert, case labels or array
 * sizes under -Wpedantic. */
#define FX_Q16_16_C(x) ((fx_q16_16_t)((x) >= 0 ? (x) * 65536.0 + 0.5 : (x) * 65536.0 - 0.5))

/* Binary angle of a literal number of degrees, rounded (constants only). */
#define FX_BAM32_DEG_C(deg) \
    ((fx_bam32_t)(int64_t)((deg) >= 0 ? (deg) * (4294967296.0 / 360.0) + 0.5 \
                                      : (deg) * (4294967296.0 / 360.0) - 0.5))

/* The estimator relies on arithmetic right shift of negative values (gcc
 * and clang on every target we build for); pin it. */
// cppcheck-suppress shiftNegativeLHS ; the point of the check
_Static_assert((-3 >> 1) == -2, "arithmetic right shift required");

/* The helpers below are a few instructions each and sit in the inner
 * loops: inline them at every optimisation level (at -Os gcc otherwise
 * calls them, which costs more than their bodies). */
#if defined(__GNUC__)
#define FX_INLINE static inline __attribute__((always_inline))
#else
#define FX_INLINE static inline
#endif

/* The opposite, for a large step called from several places: one copy of
 * it, whatever the optimisation level (at -O2 gcc would otherwise paste it
 * into each caller and the loop's flash outgrows a 64 KiB part). */
#if defined(__GNUC__)
#define EGO_NOINLINE __attribute__((noinline))
#else
#define EGO_NOINLINE
#endif

/* Arithmetic right shift by s (1..62), rounding to nearest with ties away
 * from zero. Computed on the magnitude in unsigned arithmetic, so it is
 * defined for every int64 input, INT64_MIN included. */
FX_INLINE int64_t fx_shr_round_s64(int64_t v, unsigned s)
{
    const uint64_t half = (uint64_t)1 << (s - 1u);
    if (v >= 0) {
        return (int64_t)(((uint64_t)v + half) >> s);
    }
    const uint64_t mag = (uint64_t)0 - (uint64_t)v;
    return -(int64_t)((mag + half) >> s);
}

/* Saturates a 64-bit value to int32. */
FX_INLINE int32_t fx_sat_s32(int64_t v)
{
    if (v > INT32_MAX) {
        return INT32_MAX;
    }
    if (v < INT32_MIN) {
        return INT32_MIN;
    }
    return (int32_t)v;
}

/* Q16.16 x Q2.30 -> Q16.16 (e.g. a coordinate times a cosine); rounded,
 * saturated. */
FX_INLINE fx_q16_16_t fx_mul_q16_q30(fx_q16_16_t a, fx_q2_30_t b)
{
    return fx_sat_s32(fx_shr_round_s64((int64_t)a * b, 30u));
}

/* Q16.16 x Q16.16 -> Q16.16; rounded, saturated. */
FX_INLINE fx_q16_16_t fx_mul_q16(fx_q16_16_t a, fx_q16_16_t b)
{
    return fx_sat_s32(fx_shr_round_s64((int64_t)a * b, 16u));
}

/* Saturating Q16.16 addition and subtraction. */
FX_INLINE fx_q16_16_t fx_add_q16(fx_q16_16_t a, fx_q16_16_t b)
{
    return fx_sat_s32((int64_t)a + b);
}

FX_INLINE fx_q16_16_t fx_sub_q16(fx_q16_16_t a, fx_q16_16_t b)
{
    return fx_sat_s32((int64_t)a - b);
}

/* 2^32 / (2 pi) / 2^16 = 10430.378: radians Q16.16 -> binary angle, as
 * (x * FX_BAM_PER_RAD_Q16_X128) / 128. */
#define FX_BAM_PER_RAD_Q16_X128 1335088

/* A turn (a binary angle difference) in Q16.16 radians, truncated. */
FX_INLINE int64_t fx_rad_q16_of_turn(int32_t turn)
{
    return (int64_t)turn * 128 / FX_BAM_PER_RAD_Q16_X128;
}

/* Signed difference a - b of two binary angles, in [-half, half) turn, as
 * a signed binary angle (2^31 = 180 deg). Defined for every input (no
 * implementation-defined unsigned -> signed conversion). */
FX_INLINE int32_t fx_bam32_diff(fx_bam32_t a, fx_bam32_t b)
{
    const uint32_t d = a - b;
    if (d <= (uint32_t)INT32_MAX) {
        return (int32_t)d;
    }
    return -(int32_t)(~d) - 1;
}

/* Distance between two line directions (modulo 180 deg), as a binary
 * angle in [0, 90 deg]. */
FX_INLINE fx_bam32_t fx_line_angle_diff(fx_bam32_t a, fx_bam32_t b)
{
    const uint32_t d = (a - b) & (FX_BAM32_HALF - 1u);
    return (d > FX_BAM32_QUARTER) ? FX_BAM32_HALF - d : d;
}

#endif /* FX_H */
