/* ego_fx_math.c - integer sin/cos, atan2 and square root (ego_fx_math.h).
 *
 * Integer arithmetic only: 32 x 32 -> 64-bit multiplies, 32-bit unsigned
 * divisions (UDIV on a Cortex-M3), no 64-bit division, no libgcc helper
 * calls. Every loop has a fixed bound. Design notes, error bounds and
 * measured worst errors: docs/fixed-point.md.
 */
#include "ego_fx_math.h"

#include <stdbool.h>
#include <stdint.h>

#include "ego_fx.h"
#include "ego_fx_math_tables.h"

/* ------------------------------------------------------------------------
 * sin / cos
 *
 * The angle splits into a quadrant q (top two bits) and r in [0, 2^30).
 * quarter_wave(r) returns sin and cos of r (a first-quadrant angle) from
 * the nearest of the 257 quarter-wave nodes k * 2^22 (sin and cos of a
 * node are both in fx_sin_q31: cos(node k) = sin(node 256 - k)) and the
 * offset d = r - node, |d| <= 2^21 (at most pi/1024 rad), with
 *   sin(node + d) = sin(node) cos(d) + cos(node) sin(d)
 *   cos(node + d) = cos(node) cos(d) - sin(node) sin(d)
 *   cos(d) ~ 1 - d^2/2, sin(d) ~ d (1 - d^2/6)
 * (omitted terms below 4e-12). Intermediates are unsigned fixed point, the
 * sign of d picks add or subtract.
 *
 * Exact symmetry: a tie (r halfway between two nodes) goes to the node of
 * even index. As 256 is even, r and 2^30 - r then use mirrored nodes with
 * the same |d|, so quarter_wave(2^30 - r) is quarter_wave(r) with sin and
 * cos swapped, bit for bit. That, and building every quadrant from the
 * same (sin, cos) pair of r, gives sin(-a) == -sin(a),
 * sin(a + half) == -sin(a) and cos(a) == sin(a + quarter) exactly.
 * ---------------------------------------------------------------------- */

#define SIN_NODE_SHIFT 22u /* 2^30 / FX_SIN_SEGMENTS = 2^22 binary-angle units */
_Static_assert(FX_SIN_SEGMENTS == (1u << (30u - SIN_NODE_SHIFT)), "node spacing");

/* round(pi * 2^30): d binary-angle units are d * pi * 2^-31 rad. */
#define PI_Q30 3373259426u

/* round(2^32 / 6) */
#define ONE_SIXTH_Q32 0x2AAAAAABu

/* sin and cos of the first-quadrant angle r (binary angle, r < 2^30), as
 * Q2.30 values in [0, 2^30]. */
static void quarter_wave(uint32_t r, uint32_t *s_out, uint32_t *c_out)
{
    /* Nearest node, ties to the even node. */
    const uint32_t k = (r + (1u << (SIN_NODE_SHIFT - 1u)) - 1u + ((r >> SIN_NODE_SHIFT) & 1u)) >>
                       SIN_NODE_SHIFT;
    const uint32_t node = k << SIN_NODE_SHIFT;
    const bool below = r < node;
    const uint32_t ad = below ? node - r : r - node; /* |d| <= 2^21 */

    /* u = |d| in radians, Q0.40 (u < pi/1024 * 2^40 < 2^32). */
    const uint32_t u = (uint32_t)(((uint64_t)ad * PI_Q30 + (1u << 20)) >> 21);
    /* u^2, Q0.48 (< 2^31.4). */
    const uint32_t u2 = (uint32_t)(((uint64_t)u * u + (1u << 31)) >> 32);
    /* u^2 / 6, Q0.48. */
    const uint32_t u2_6 = (uint32_t)(((uint64_t)u2 * ONE_SIXTH_Q32) >> 32);
    /* v = sin(d) ~ u (1 - u^2/6), Q0.40. */
    const uint32_t v = u - (uint32_t)(((uint64_t)u * u2_6) >> 48);

    const uint64_t sk = fx_sin_q31[k];                   /* Q1.31 */
    const uint64_t ck = fx_sin_q31[FX_SIN_SEGMENTS - k]; /* Q1.31 */

    /* Products at 2^-62: node value times cos(d) ~ 1 - u^2/2, and node
     * value times sin(d). */
    const uint64_t s_cos = (sk << 31) - ((sk * u2) >> 18);
    const uint64_t c_cos = (ck << 31) - ((ck * u2) >> 18);
    const uint64_t s_sin = (sk * v) >> 9;
    const uint64_t c_sin = (ck * v) >> 9;

    uint64_t s;
    uint64_t c;
    if (below) {
        s = s_cos - c_sin;
        c = c_cos + s_sin;
    } else {
        s = s_cos + c_sin;
        c = c_cos - s_sin;
    }
    /* 2^-62 -> Q2.30, rounded (all values are non-negative). */
    *s_out = (uint32_t)((s + ((uint64_t)1 << 31)) >> 32);
    *c_out = (uint32_t)((c + ((uint64_t)1 << 31)) >> 32);
}

void fx_sincos(fx_bam32_t angle, fx_q2_30_t *sin_out, fx_q2_30_t *cos_out)
{
    uint32_t s;
    uint32_t c;
    quarter_wave(angle & (FX_BAM32_QUARTER - 1u), &s, &c);
    const fx_q2_30_t sv = (fx_q2_30_t)s; /* both <= 2^30 */
    const fx_q2_30_t cv = (fx_q2_30_t)c;
    switch (angle >> 30) {
    case 0u:
        *sin_out = sv;
        *cos_out = cv;
        break;
    case 1u:
        *sin_out = cv;
        *cos_out = -sv;
        break;
    case 2u:
        *sin_out = -sv;
        *cos_out = -cv;
        break;
    default:
        *sin_out = -cv;
        *cos_out = sv;
        break;
    }
}

fx_q2_30_t fx_sin(fx_bam32_t angle)
{
    fx_q2_30_t s;
    fx_q2_30_t c;
    fx_sincos(angle, &s, &c);
    return s;
}

fx_q2_30_t fx_cos(fx_bam32_t angle)
{
    fx_q2_30_t s;
    fx_q2_30_t c;
    fx_sincos(angle, &s, &c);
    return c;
}

/* ------------------------------------------------------------------------
 * Helpers shared by atan2 and the square root
 * ---------------------------------------------------------------------- */

/* Leading zero bits of x (x != 0): the CLZ instruction where the compiler
 * offers it, else a fixed six-step binary search. */
static unsigned clz64(uint64_t x)
{
#if defined(__GNUC__)
    return (unsigned)__builtin_clzll(x);
#else
    unsigned n = 0u;
    if ((x >> 32) == 0u) {
        n += 32u;
        x <<= 32;
    }
    if ((x >> 48) == 0u) {
        n += 16u;
        x <<= 16;
    }
    if ((x >> 56) == 0u) {
        n += 8u;
        x <<= 8;
    }
    if ((x >> 60) == 0u) {
        n += 4u;
        x <<= 4;
    }
    if ((x >> 62) == 0u) {
        n += 2u;
        x <<= 2;
    }
    if ((x >> 63) == 0u) {
        n += 1u;
    }
    return n;
#endif
}

/* ------------------------------------------------------------------------
 * atan2
 *
 * |x| and |y| as uint64 (INT64_MIN included); the larger one, big, is
 * shifted to l in [2^31, 2^32) (left: exact; right: truncated) and the
 * smaller one by the same amount (right: rounded) to s. Then
 * t = s / l in Q0.32, rounded, by a 64/32 division built from two 32/16
 * digit steps (32-bit UDIV), and atan(t) from a cubic per 1/128 of [0, 1)
 * (fx_atan_seg). Octant and quadrant come back by exact integer
 * identities: swapped -> quarter - phi, x < 0 -> half - a, y < 0 -> -a.
 * ---------------------------------------------------------------------- */

/* floor((hi * 2^32 + lo) / d) for d >= 2^31 and hi < d (the quotient fits
 * in 32 bits). Knuth's algorithm D with 16-bit digits (Hacker's Delight,
 * divlu): each digit estimate is at most 2 too large. */
static uint32_t div_64_32(uint32_t hi, uint32_t lo, uint32_t d)
{
    const uint32_t b = 0x10000u;
    const uint32_t d1 = d >> 16;
    const uint32_t d0 = d & 0xFFFFu;
    const uint32_t lo1 = lo >> 16;
    const uint32_t lo0 = lo & 0xFFFFu;

    uint32_t q1 = hi / d1;
    uint32_t rhat = hi - q1 * d1;
    for (unsigned i = 0u; i < 2u; i++) {
        if (q1 < b && q1 * d0 <= ((rhat << 16) | lo1)) {
            break;
        }
        q1--;
        rhat += d1;
        if (rhat >= b) {
            break;
        }
    }
    /* Partial remainder (hi * 2^16 + lo1) - q1 * d, < d: computed mod 2^32. */
    const uint32_t mid = (hi << 16) + lo1 - q1 * d;

    uint32_t q0 = mid / d1;
    rhat = mid - q0 * d1;
    for (unsigned i = 0u; i < 2u; i++) {
        if (q0 < b && q0 * d0 <= ((rhat << 16) | lo0)) {
            break;
        }
        q0--;
        rhat += d1;
        if (rhat >= b) {
            break;
        }
    }
    return (q1 << 16) + q0;
}

/* atan(t) for t in [0, 1) (Q0.32), in binary-angle units, rounded:
 * Horner on the segment's cubic with u in Q0.31, every partial sum within
 * int32 (checked by the generator), final sum at 2^-32 binary angle. */
static uint32_t atan_unit(uint32_t t)
{
    const fx_atan_seg_t *c = &fx_atan_seg[t >> 25];
    const int32_t u = (int32_t)((t & 0x01FFFFFFu) << 6);
    int32_t acc = c->c3;
    acc = c->c2 + (int32_t)fx_shr_round_s64((int64_t)acc * u,
                                            31u + FX_ATAN_C3_FRAC - FX_ATAN_C2_FRAC);
    acc = c->c1 + (int32_t)fx_shr_round_s64((int64_t)acc * u,
                                            31u + FX_ATAN_C2_FRAC - FX_ATAN_C1_FRAC);
    const int64_t phi = (int64_t)((uint64_t)c->c0 << (32u - FX_ATAN_C0_FRAC)) +
                        fx_shr_round_s64((int64_t)acc * u, 31u + FX_ATAN_C1_FRAC - 32u);
    return (uint32_t)fx_shr_round_s64(phi, 32u);
}
_Static_assert(FX_ATAN_SEGMENTS == 128u, "atan_unit indexes with t >> 25");
_Static_assert(FX_ATAN_C1_FRAC >= 2u && FX_ATAN_C1_FRAC < FX_ATAN_C2_FRAC &&
                   FX_ATAN_C2_FRAC < FX_ATAN_C3_FRAC,
               "atan coefficient scales");

static uint64_t magnitude(int64_t v)
{
    return v < 0 ? (uint64_t)0 - (uint64_t)v : (uint64_t)v;
}

/* The angle of (x, y) from phi = atan(small / big) in the first octant:
 * by the exact identities of the octant and the quadrant. */
static fx_bam32_t unfold_octant(uint32_t phi, bool steep, int64_t x, int64_t y)
{
    uint32_t a = steep ? FX_BAM32_QUARTER - phi : phi; /* first quadrant */
    if (x < 0) {
        a = FX_BAM32_HALF - a;
    }
    if (y < 0) {
        a = 0u - a;
    }
    return a;
}

fx_bam32_t fx_atan2(int64_t y, int64_t x)
{
    const uint64_t ax = magnitude(x);
    const uint64_t ay = magnitude(y);
    const bool steep = ay > ax;
    const uint64_t big = steep ? ay : ax;
    const uint64_t small = steep ? ax : ay;
    if (big == 0u) {
        return 0u;
    }

    /* big -> l in [2^31, 2^32), small -> s by the same shift. */
    const unsigned z = clz64(big);
    uint32_t l;
    uint64_t s;
    if (z >= 32u) {
        l = (uint32_t)(big << (z - 32u));
        s = small << (z - 32u);
    } else {
        const unsigned sh = 32u - z;
        l = (uint32_t)(big >> sh);
        s = (small >> sh) + ((small >> (sh - 1u)) & 1u);
    }

    /* phi = atan(small / big) in [0, 1/8 turn]. */
    uint32_t phi;
    if (s >= l) {
        phi = FX_BAM32_QUARTER / 2u; /* |y| == |x| (or within rounding of it) */
    } else {
        /* t = round(s * 2^32 / l) < 2^32 as s < l. */
        phi = atan_unit(div_64_32((uint32_t)s, l >> 1, l));
    }

    return unfold_octant(phi, steep, x, y);
}

unsigned fx_bits_u32(uint32_t d)
{
    return 64u - clz64((uint64_t)d);
}

/* atan(k / 32), k = 0..32, in binary angle (2^32 a turn), rounded. */
static const uint32_t atan_32nds[33] = {
    0u,         21354465u,  42667331u,  63897482u,  85004756u,  105950391u, 126697423u,
    147211045u, 167458907u, 187411349u, 207041579u, 226325781u, 245243172u, 263775993u,
    281909457u, 299631651u, 316933406u, 333808132u, 350251643u, 366261957u, 381839095u,
    396984877u, 411702716u, 425997422u, 439875013u, 453342536u, 466407904u, 479079736u,
    491367227u, 503280012u, 514828063u, 526021581u, 536870912u};

/* atan2(y, x) as a binary angle, within FX_ATAN2_QUICK_ERROR: for the
 * matching passes, whose walk only needs a start near the right place
 * (find_match widens its cone by the error). The octant by exact
 * identities as fx_atan2; t = small / big in Q16 by one 32-bit division
 * after both are cut to 16 significant bits of big (error < 2^-14 + 2^-16),
 * and atan(t) interpolated in a table of 32nds (error < 8e-5 rad). */
fx_bam32_t fx_atan2_quick(int64_t y, int64_t x)
{
    uint64_t ax = (x < 0) ? (uint64_t)0 - (uint64_t)x : (uint64_t)x;
    uint64_t ay = (y < 0) ? (uint64_t)0 - (uint64_t)y : (uint64_t)y;
    const bool steep = ay > ax;
    uint64_t big = steep ? ay : ax;
    uint64_t small = steep ? ax : ay;
    for (unsigned k = 0u; k < 32u && big > UINT32_MAX; k++) { /* beyond any scan */
        big >>= 1;
        small >>= 1;
    }
    uint32_t b = (uint32_t)big;
    uint32_t s = (uint32_t)small;
    if (b == 0u) {
        return 0u;
    }
    const unsigned n = fx_bits_u32(b);
    if (n > 16u) {
        b >>= n - 16u;
        s >>= n - 16u;
    }
    const uint32_t t = (s << 16) / b; /* s <= b < 2^16: Q16, 0..65536 */
    const uint32_t i = t >> 11;
    uint32_t phi = atan_32nds[i];
    if (i < 32u) {
        const uint64_t step = (uint64_t)(atan_32nds[i + 1u] - phi) * (t & 0x7FFu);
        phi += (uint32_t)(step >> 11);
    }
    return unfold_octant(phi, steep, x, y);
}

/* ------------------------------------------------------------------------
 * Square root
 *
 * v is shifted left by an even amount z to w >= 2^62, and the floor root
 * and remainder of w are built top down with Zimmermann's Karatsuba square
 * root step (P. Zimmermann, "Karatsuba Square Root", INRIA RR-3805, 1999;
 * Brent & Zimmermann, Modern Computer Arithmetic, algorithm SqrtRem): from
 * (s', r') of the top half of the bits, with beta = 2^(half of the new
 * digits),
 *   q = floor((r' beta + a1) / (2 s')), u = the remainder,
 *   s = s' beta + q, r = u beta + a0 - q^2, and if r < 0: r += 2s - 1, s--.
 * w >= 2^62 makes every level normalised (top quarter >= beta / 4), which
 * the step needs for the single correction to suffice. 4 -> 8 -> 16 -> 32
 * bits in 32-bit arithmetic, 32 -> 64 bits with the two 64-bit values it
 * needs. floor(sqrt(v)) = floor(sqrt(w)) >> z/2; it is rounded up when
 * v - root^2 > root, i.e. v >= root^2 + root + 1 = (root + 1/2)^2 + 3/4.
 * ---------------------------------------------------------------------- */

uint32_t fx_sqrt_u64(uint64_t v)
{
    if (v == 0u) {
        return 0u;
    }
    const unsigned z = clz64(v) & ~1u;
    const uint64_t w = v << z;
    const uint32_t w_hi = (uint32_t)(w >> 32); /* >= 2^30 */

    /* Top 4 bits m in [4, 16): root 2 or 3. */
    uint32_t m = w_hi >> 28;
    uint32_t s = (m >= 9u) ? 3u : 2u;
    uint32_t r = m - s * s;

    /* 4 -> 8 -> 16 -> 32 bits of w_hi. */
    for (unsigned bits = 4u; bits <= 16u; bits *= 2u) {
        const unsigned half = bits / 2u;
        const uint32_t mask = (1u << half) - 1u;
        m = w_hi >> (32u - 2u * bits);
        const uint32_t a1 = (m >> half) & mask;
        const uint32_t a0 = m & mask;
        const uint32_t n = (r << half) | a1;
        const uint32_t q = n / (2u * s);
        const uint32_t rem = n - q * 2u * s;
        s = (s << half) + q;
        const uint32_t low = (rem << half) | a0;
        if (low >= q * q) {
            r = low - q * q;
        } else {
            r = low + 2u * s - 1u - q * q;
            s--;
        }
    }

    /* 32 -> 64 bits: s < 2^16, r <= 2s, so r * 2^16 + a1 < 2^33; its half
     * fits 32 bits and floor(floor(n / 2) / s) = floor(n / (2 s)). */
    const uint64_t n = ((uint64_t)r << 16) | ((w >> 16) & 0xFFFFu);
    const uint32_t q = (uint32_t)(n >> 1) / s; /* <= 2^16 */
    const uint64_t rem = n - (uint64_t)q * 2u * s;
    uint64_t root64 = ((uint64_t)s << 16) + q;
    if (((rem << 16) | (w & 0xFFFFu)) < (uint64_t)q * q) {
        root64--;
    }

    uint32_t root = (uint32_t)(root64 >> (z / 2u));
    const uint64_t rest = v - (uint64_t)root * root;
    if (rest > root && root != UINT32_MAX) {
        root++;
    }
    return root;
}
