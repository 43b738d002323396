#!/usr/bin/env python3
"""gen_fx_tables.py - writes estimator/ego_fx_math_tables.h (the tables of ego_fx_math.c).

    python3 host_tests/tools/gen_fx_tables.py > estimator/ego_fx_math_tables.h
    python3 host_tests/tools/gen_fx_tables.py --check     # design figures, stderr

Standard library only. Every value is computed with decimal arithmetic at 60
significant digits (pi by Machin's formula, sin and atan by their series) and
rounded once, so the output does not depend on the host's floating point.

Tables (docs/fixed-point.md explains the kernels):

  fx_sin_q31[257]   sin(k * pi / 512), k = 0..256, unsigned Q1.31 (1.0 = 2^31).
                    The quarter wave at 256 nodes; cos of node k is entry
                    256 - k.
  fx_atan_seg[128]  atan(t) / (2 pi) in binary-angle units (2^32 = one turn)
                    for t in [0, 1), 128 segments of width 1/128, each a cubic
                    c0 + c1 u + c2 u^2 + c3 u^3 in the local u in [0, 1)
                    that interpolates atan at u = 0, 1/2 - d, 1/2 + d, 1
                    (d = (sqrt(2) - 1) / 2: pinned ends, so neighbouring
                    segments meet, and the node error polynomial has its
                    smallest maximum). c0 is unsigned in units of 2^-3
                    binary angle, c1..c3 signed in units of 2^-S1..2^-S3.
"""
import sys
from decimal import Decimal, getcontext

getcontext().prec = 60

SIN_SEGMENTS = 256  # quarter wave
ATAN_SEGMENTS = 128  # t in [0, 1)
ATAN_C0_FRAC = 3  # c0 in units of 2^-3 binary angle (c0 < 2^29 -> fits uint32)
HEADROOM = 2 ** 30  # |scaled coefficient and every Horner partial sum| <= 2^30


def atan_series(x):
    """atan(x) by its Taylor series, for |x| <= 0.25."""
    total = Decimal(0)
    power = x
    x2 = x * x
    n = 1
    while True:
        term = power / n
        if abs(term) < Decimal(10) ** -70:
            return total
        total += term if (n // 2) % 2 == 0 else -term
        power *= x2
        n += 2


def atan(x):
    """atan(x) for |x| <= 1: halve the angle twice, then the series."""
    y = x
    for _ in range(2):
        y = y / (1 + (1 + y * y).sqrt())
    return 4 * atan_series(y)


PI = 16 * atan_series(Decimal(1) / 5) - 4 * atan_series(Decimal(1) / 239)


def sin(x):
    """sin(x) by its Taylor series, for |x| <= pi / 2."""
    total = Decimal(0)
    term = x
    n = 1
    while abs(term) >= Decimal(10) ** -70:
        total += term
        term = -term * x * x / ((n + 1) * (n + 2))
        n += 2
    return total


def round_half_away(v):
    """Nearest integer to the Decimal v, ties away from zero."""
    if v >= 0:
        return int((v + Decimal("0.5")).to_integral_value(rounding="ROUND_FLOOR"))
    return -int((-v + Decimal("0.5")).to_integral_value(rounding="ROUND_FLOOR"))


TURN = Decimal(2) ** 32  # binary-angle units per turn


def atan_bam(t):
    """atan(t) in binary-angle units (real, not rounded)."""
    return atan(t) / (2 * PI) * TURN


def sin_table():
    return [round_half_away(sin(PI * k / (2 * SIN_SEGMENTS)) * 2 ** 31)
            for k in range(SIN_SEGMENTS + 1)]


def cubic_through(us, fs):
    """Power-basis coefficients [c0, c1, c2, c3] of the cubic through (us, fs)."""
    # Newton divided differences, then expand.
    n = len(us)
    coef = list(fs)
    for j in range(1, n):
        for i in range(n - 1, j - 1, -1):
            coef[i] = (coef[i] - coef[i - 1]) / (us[i] - us[i - j])
    poly = [Decimal(0)] * n
    for i in range(n - 1, -1, -1):
        # poly = poly * (u - us[i]) + coef[i]
        new = [Decimal(0)] * n
        for k in range(n - 1):
            new[k + 1] += poly[k]
            new[k] -= poly[k] * us[i]
        new[0] += coef[i]
        poly = new
    return poly


def atan_segments():
    d = ((Decimal(2).sqrt()) - 1) / 2
    us = [Decimal(0), Decimal("0.5") - d, Decimal("0.5") + d, Decimal(1)]
    segs = []
    for j in range(ATAN_SEGMENTS):
        fs = [atan_bam((j + u) / ATAN_SEGMENTS) for u in us]
        segs.append(cubic_through(us, fs))
    return segs


def frac_bits_for(values):
    """Largest S with max |v| * 2^S <= HEADROOM."""
    m = max(abs(v) for v in values)
    s = 0
    while m * 2 ** (s + 1) <= HEADROOM:
        s += 1
    return s


def quantise_atan(segs):
    s1 = frac_bits_for([c[1] for c in segs])
    s2 = frac_bits_for([c[2] for c in segs])
    s3 = frac_bits_for([c[3] for c in segs])
    rows = []
    for c in segs:
        rows.append((round_half_away(c[0] * 2 ** ATAN_C0_FRAC),
                     round_half_away(c[1] * 2 ** s1),
                     round_half_away(c[2] * 2 ** s2),
                     round_half_away(c[3] * 2 ** s3)))
    for r in rows:
        assert 0 <= r[0] < 2 ** 32
        for v in r[1:]:
            assert abs(v) <= HEADROOM
    return (s1, s2, s3), rows


def shr_round(v, s):
    """fx_shr_round_s64: nearest, ties away from zero."""
    half = 1 << (s - 1)
    if v >= 0:
        return (v + half) >> s
    return -((-v + half) >> s)


def atan_eval(t, shifts, rows):
    """Bit-exact model of atan_unit() in ego_fx_math.c. t: Q0.32 in [0, 2^32)."""
    s1, s2, s3 = shifts
    c0, c1, c2, c3 = rows[t >> 25]
    u = (t & 0x01FFFFFF) << 6
    acc = c3
    acc = c2 + shr_round(acc * u, 31 + s3 - s2)
    assert abs(acc) < 2 ** 31
    acc = c1 + shr_round(acc * u, 31 + s2 - s1)
    assert abs(acc) < 2 ** 31
    phi = (c0 << (32 - ATAN_C0_FRAC)) + shr_round(acc * u, 31 + s1 - 32)
    return shr_round(phi, 32)


def check(sin_q31, shifts, rows, segs):
    """Design figures: fit error of the real cubics, and error of the
    bit-exact integer model against atan, on a sample of t."""
    out = sys.stderr
    worst_fit = Decimal(0)
    worst_int = Decimal(0)
    worst_t = 0
    n = 0
    for j in range(ATAN_SEGMENTS):
        for i in range(65):
            u = Decimal(i) / 64
            t_real = (j + u) / ATAN_SEGMENTS
            exact = atan_bam(t_real)
            c = segs[j]
            p = c[0] + u * (c[1] + u * (c[2] + u * c[3]))
            worst_fit = max(worst_fit, abs(p - exact))
            if i < 64:
                t = (j << 25) + (i << 19) + 12345
                e = atan_eval(t, shifts, rows) - atan_bam(Decimal(t) / TURN)
                n += 1
                if abs(e) > worst_int:
                    worst_int = abs(e)
                    worst_t = t
    print("atan cubic fit (real coefficients): worst %.4f LSB" % worst_fit, file=out)
    print("atan integer model incl. final rounding: worst %.4f LSB at t = 0x%08X (%d samples)"
          % (worst_int, worst_t, n), file=out)
    print("atan coefficient scales: S1=%d S2=%d S3=%d" % shifts, file=out)
    worst_sin = max(abs(Decimal(sin_q31[k]) - sin(PI * k / (2 * SIN_SEGMENTS)) * 2 ** 31)
                    for k in range(SIN_SEGMENTS + 1))
    print("sin table rounding: worst %.4f Q1.31 LSB" % worst_sin, file=out)


def emit(sin_q31, shifts, rows):
    w = sys.stdout.write
    w("/* ego_fx_math_tables.h - tables of ego_fx_math.c (static const, flash). GENERATED,\n"
      " * do not edit; regenerate with\n"
      " *\n"
      " *   python3 host_tests/tools/gen_fx_tables.py > estimator/ego_fx_math_tables.h\n"
      " *\n"
      " * Included by ego_fx_math.c only. docs/fixed-point.md describes the kernels.\n"
      " */\n"
      "#ifndef FX_MATH_TABLES_H\n"
      "#define FX_MATH_TABLES_H\n"
      "\n"
      "#include <stdint.h>\n"
      "\n")
    w("/* sin(k * pi / 512), k = 0..%d, unsigned Q1.31 (1.0 = 2^31), rounded to\n"
      " * nearest: the quarter wave at %d segments. cos of node k is entry\n"
      " * %d - k. %d bytes. */\n" % (SIN_SEGMENTS, SIN_SEGMENTS, SIN_SEGMENTS,
                                     4 * (SIN_SEGMENTS + 1)))
    w("#define FX_SIN_SEGMENTS %du\n" % SIN_SEGMENTS)
    w("static const uint32_t fx_sin_q31[FX_SIN_SEGMENTS + 1u] = {\n")
    for i in range(0, len(sin_q31), 6):
        w("    " + " ".join("0x%08Xu," % v for v in sin_q31[i:i + 6]) + "\n")
    w("};\n\n")
    s1, s2, s3 = shifts
    w("/* atan(t) / (2 pi) in binary-angle units (2^32 = one turn) for t in\n"
      " * [0, 1): segment j covers t in [j, j + 1) / %d; with u in [0, 1) the\n"
      " * local position, atan = c0 / 2^%d + c1 u / 2^%d + c2 u^2 / 2^%d\n"
      " * + c3 u^3 / 2^%d. Each cubic interpolates atan at u = 0, 1/2 - d,\n"
      " * 1/2 + d and 1 (d = (sqrt(2) - 1) / 2). %d bytes. */\n"
      % (ATAN_SEGMENTS, ATAN_C0_FRAC, s1, s2, s3, 16 * ATAN_SEGMENTS))
    w("#define FX_ATAN_SEGMENTS %du\n" % ATAN_SEGMENTS)
    w("#define FX_ATAN_C0_FRAC %du\n" % ATAN_C0_FRAC)
    w("#define FX_ATAN_C1_FRAC %du\n" % s1)
    w("#define FX_ATAN_C2_FRAC %du\n" % s2)
    w("#define FX_ATAN_C3_FRAC %du\n" % s3)
    w("\n"
      "typedef struct {\n"
      "    uint32_t c0;\n"
      "    int32_t c1;\n"
      "    int32_t c2;\n"
      "    int32_t c3;\n"
      "} fx_atan_seg_t;\n"
      "\n")
    w("static const fx_atan_seg_t fx_atan_seg[FX_ATAN_SEGMENTS] = {\n")
    for r in rows:
        w("    {0x%08Xu, %d, %d, %d},\n" % r)
    w("};\n\n#endif /* FX_MATH_TABLES_H */\n")


def main():
    sin_q31 = sin_table()
    segs = atan_segments()
    shifts, rows = quantise_atan(segs)
    if len(sys.argv) > 1 and sys.argv[1] == "--check":
        check(sin_q31, shifts, rows, segs)
        return 0
    if len(sys.argv) > 1:
        print("usage: gen_fx_tables.py [--check]", file=sys.stderr)
        return 2
    emit(sin_q31, shifts, rows)
    return 0


if __name__ == "__main__":
    sys.exit(main())
