#!/usr/bin/env python3
"""Where a target image spends its instructions, per function.

A replay image built with TARGET_PC_SAMPLING (docs/firmware.md) samples the
interrupted program counter every 39 880 instructions and prints, after its
CSV, one line per 64-byte piece of flash that was hit:

    # pc_sample at=ADDRESS count=N

This script maps each piece to the function holding its middle (the image's
symbol table, arm-none-eabi-nm) and prints the share of the samples per
function, largest first. A piece that straddles two small functions counts
for one of them: read the figures to a percent or so.

usage: pc_profile.py IMAGE.elf OUTPUT [TOP]
"""
import bisect
import collections
import re
import subprocess
import sys

BUCKET = 64


def functions(elf):
    """(start, size, name) of every function symbol, sorted by address."""
    out = subprocess.run(["arm-none-eabi-nm", "-S", "--defined-only", elf],
                         capture_output=True, text=True, check=True).stdout
    found = []
    for line in out.splitlines():
        parts = line.split()
        if len(parts) == 4 and parts[2] in "tTwW":
            found.append((int(parts[0], 16) & ~1, int(parts[1], 16), parts[3]))
    return sorted(found)


def main():
    if len(sys.argv) not in (3, 4):
        sys.exit(__doc__.strip().splitlines()[-1])
    syms = functions(sys.argv[1])
    starts = [s[0] for s in syms]
    shares = collections.Counter()
    total = 0
    with open(sys.argv[2], encoding="ascii", errors="replace") as f:
        for line in f:
            m = re.match(r"# pc_sample at=(\d+) count=(\d+)", line)
            if not m:
                continue
            middle = int(m.group(1)) + BUCKET // 2
            n = int(m.group(2))
            total += n
            i = bisect.bisect_right(starts, middle) - 1
            inside = i >= 0 and middle < syms[i][0] + syms[i][1] + BUCKET
            shares[syms[i][2] if inside else "?"] += n
    if total == 0:
        sys.exit("no pc_sample lines: was the image built with TARGET_PC_SAMPLING?")
    top = int(sys.argv[3]) if len(sys.argv) == 4 else 25
    print(f"{total} samples")
    for name, n in shares.most_common(top):
        print(f"{100.0 * n / total:5.1f} % {name}")


if __name__ == "__main__":
    main()
