#!/usr/bin/env python3
"""estimator_seed.py - one fuzz_estimator input (host_tests/fuzz/fuzz_estimator.c
describes the format), or with --itcp one fuzz_itcp input (fuzz_itcp.c),
from the decoded scans of a recording.

    lmsego scans FILE | estimator_seed.py [options] OUT

Reads `lmsego scans` lines (index unit_mm n v1..vn, millimetres, negative:
a special value) and writes OUT: the setup byte, then FULL scans from FIRST
on, each with every EVERY-th value (a 180-degree scan keeps its span when
EVERY divides n - 1), then AGAIN scans again of the last one, each turned
TURN 2^-16 turns and its ranges moved DELTA units. With --itcp: the scans
FIRST and FIRST + 1 (--full 2), from the zero pose, ITCP's defaults, then
PROBES probes along the scan's middle beam. Ranges are written in the
unit the setup names (bits 6-7: 0 mm, 1 cm, 2 quarter mm); special values
and ranges past 16 bits become 0 (no range). host_tests/fuzz/README.md
lists the seeds made with it.
"""
import argparse
import struct
import sys

UNIT_UM = {0: 1000, 1: 10000, 2: 250}


def read_scans():
    """The `lmsego scans` lines on stdin: index -> values (mm, < 0 special)."""
    scans = {}
    for line in sys.stdin:
        f = line.split()
        if len(f) >= 3:
            scans[int(f[0])] = [int(v) for v in f[3:]]
    return scans


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("out", help="the input file to write")
    ap.add_argument("--setup", type=lambda v: int(v, 0), default=0x40,
                    help="setup byte (default 0x40: unbounded, cm, no prior)")
    ap.add_argument("--first", type=int, default=0, help="first scan index (default 0)")
    ap.add_argument("--full", type=int, default=4, help="scans with their own ranges, 1..4")
    ap.add_argument("--every", type=int, default=1, help="keep every EVERY-th value")
    ap.add_argument("--step-us", type=int, default=13333, help="time between scans, us")
    ap.add_argument("--span-deg", type=float, default=180.0, help="the scan's sweep, degrees")
    ap.add_argument("--again", type=int, default=0, help="scans again after the last, 0..36")
    ap.add_argument("--turn", type=int, default=0, help="each scan again turned, 2^-16 turns")
    ap.add_argument("--delta", type=int, default=0, help="each scan again: ranges + DELTA units")
    ap.add_argument("--budget", type=int, default=0,
                    help="setup bit 0: the budget in 64ths of the live one, 1..255 (0: it)")
    ap.add_argument("--max-search", type=int, default=0,
                    help="setup bit 0: max_search_scans, 1..255 (0: the default)")
    ap.add_argument("--itcp", action="store_true", help="a fuzz_itcp input (setup bits 5-6: unit)")
    ap.add_argument("--probes", type=int, default=8, help="--itcp: probes, 0..8")
    ap.add_argument("--timing", default=None,
                    help="PASSES,PASS_US,BEAM_NS of every scan (setup bit 3)")
    args = ap.parse_args()
    if not 1 <= args.full <= 4 or not 0 <= args.again <= 36 or args.every < 1:
        ap.error("--full 1..4, --again 0..36, --every >= 1")
    if args.itcp:
        return write_itcp(args, ap)
    if args.setup & 0x32:
        ap.error("a prior (bit 1), an origin (bit 4) or raw fields (bit 5) are not written by this script")
    unit_pick = (args.setup >> 6) & 3
    if unit_pick == 3:
        ap.error("setup bits 6-7: 0, 1 or 2 (a unit from the input is not written)")
    unit_um = UNIT_UM[unit_pick]
    timing = b""
    if args.setup & 8:
        if args.timing is None:
            ap.error("setup bit 3 needs --timing")
        passes, pass_us, beam_ns = (int(v) for v in args.timing.split(","))
        timing = struct.pack("<BHH", passes, pass_us, beam_ns // 16)

    scans = read_scans()
    out = bytearray([args.setup])
    if args.setup & 1:
        out += bytes([args.budget, args.max_search])  # 0, 0: the live defaults
    count = 0
    for i in range(args.first, args.first + args.full):
        values = scan_values(scans, i, args.every)
        count = len(values)
        # The sweep in 128ths of a turn (options bits 1-7 hold it - 1).
        sweep = round(args.span_deg / 360 * 128)
        options = (sweep - 1) << 1
        out += struct.pack("<BBII", count - 1, options, args.step_us, first_bearing(args.span_deg))
        out += range_bytes(values, unit_um)
        out += timing
    for _ in range(args.again):
        out += struct.pack("<BBIhh", 253, options, args.step_us, args.turn, args.delta)
        out += timing
    with open(args.out, "wb") as f:
        f.write(out)
    print(f"{args.out}: {len(out)} bytes, {args.full} + {args.again} scans of {count} values")


def scan_values(scans, i, every):
    """Every every-th value of scan i, at most 181 (what the targets read)."""
    if i not in scans:
        sys.exit(f"estimator_seed.py: no scan {i} in the input")
    values = scans[i][::every]
    if len(values) > 181:
        sys.exit(f"estimator_seed.py: {len(values)} values: at most 181 are read")
    return values


def first_bearing(span_deg):
    """The first beam of a scan centred on the x axis, a 32-bit binary angle."""
    return (-round(span_deg / 2 / 360 * 2**32)) % 2**32


def range_bytes(values, unit_um):
    """The ranges as u16 in the unit; special values and overflows: 0."""
    out = bytearray()
    for v in values:
        r = round(v * 1000 / unit_um) if v > 0 else 0
        out += struct.pack("<H", r if r <= 65535 else 0)
    return out


def write_itcp(args, ap):
    if args.setup & 0x98:
        ap.error("--itcp: setup bits 3, 4 and 7 are not written by this script")
    unit_pick = (args.setup >> 5) & 3
    if unit_pick == 3:
        ap.error("--itcp: setup bits 5-6: 0, 1 or 2")
    unit_um = UNIT_UM[unit_pick]
    scans = read_scans()
    out = bytearray([args.setup])
    out += struct.pack("<IIiiH", 0, 0, 0, 0, 0)  # main direction, pose, meter: least
    for i in (args.first, args.first + 1):
        values = scan_values(scans, i, args.every)
        # fuzz_itcp: sweep 1 + v 256ths of a turn.
        sweep_v = round(args.span_deg / 360 * 256) - 1
        out += struct.pack("<BBI", len(values) - 1, sweep_v, first_bearing(args.span_deg))
        out += range_bytes(values, unit_um)
    out += struct.pack("<HH", 300, 500)  # probes' radius and margin, mm
    middle = scan_values(scans, args.first, args.every)
    r_mm = max(v for v in middle if v > 0)
    for k in range(args.probes):
        # Along the x axis (the middle beam), from near to beyond the far return.
        out += struct.pack("<hh", round(r_mm / 10 * (k + 1) / args.probes * 1.2), (k - 4) * 5)
    with open(args.out, "wb") as f:
        f.write(out)
    print(f"{args.out}: {len(out)} bytes, two scans of {len(middle)} values, {args.probes} probes")


if __name__ == "__main__":
    main()
