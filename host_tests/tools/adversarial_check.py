#!/usr/bin/env python3
"""Checks `lmsego replay --budget default` of the adversarial recording
(host_tests/data/recordings/adversarial_361_cm.lms: `lmsgen --adversarial`,
SCANS scans of each hard case in turn) for what issue 15 asks of them:
defined flags, and no motion claimed that the scans cannot support.

usage: adversarial_check.py REPLAY.csv

Per block (the first line of each, which spans the change of case, is not
judged):
- every value invalid, one point, two points, a straight wall, all at one
  range, all at maximum range, special values alternating, a room and its
  mirror image alternating: every line carries a flag (the motion is not, or
  not wholly, measured);
- one room scan repeated: no motion (under 5 mm and 0.1 deg);
- a zig-zag at the range limit, repeated: a flag, or no motion. Its teeth
  (0.7 m wide at 81.8 m) fix the turn locally but repeat every two beams: a
  search may take a turn of 1 deg for none (the rotation is then flagged
  weak), while tracking with every beam kept stays at the truth.
Exits 1 with one line per violation, else 0. Standard library only.
"""
import csv
import math
import sys

SCANS = 8  # lmsgen's ADVERSARIAL_SCANS
KINDS = ['all invalid', 'one point', 'two points', 'straight wall', 'one range',
         'zig-zag at the limit', 'all at maximum', 'special values', 'room repeated',
         'room and mirror']


def main():
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    with open(sys.argv[1], newline='') as f:
        rows = list(csv.DictReader(f))
    if len(rows) != SCANS * len(KINDS) - 1:
        print('expected %d lines, got %d' % (SCANS * len(KINDS) - 1, len(rows)))
        return 1
    bad = []
    for row in rows:
        scan = int(row['scan'])
        kind = KINDS[scan // SCANS]
        if scan % SCANS == 0:
            continue
        flags = int(row['flags'])
        still = flags == 0 and kind == 'zig-zag at the limit'
        if kind == 'room repeated' or still:
            dx, dy, dt = (float(row[k]) for k in ('dx_m', 'dy_m', 'dtheta_rad'))
            if math.hypot(dx, dy) > 0.005 or abs(math.degrees(dt)) > 0.1:
                bad.append('scan %d (%s): motion %.4f %.4f %.3f deg' %
                           (scan, kind, dx, dy, math.degrees(dt)))
        elif flags == 0:
            bad.append('scan %d (%s): no flag' % (scan, kind))
    for line in bad:
        print(line)
    return 1 if bad else 0


if __name__ == '__main__':
    sys.exit(main())
