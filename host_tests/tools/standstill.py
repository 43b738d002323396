#!/usr/bin/env python3
"""standstill.py TRUTH CSV: what `lmsego replay` says while the vehicle stands.

TRUTH is a pairs file of lmsworld (`i j dx dy dtheta`), CSV the output of
`lmsego replay`. Over the lines whose true motion is none (the vehicle
standing, e.g. in stopgo's queue), prints one line: how many, the drift
(the length of the sum of their translations: where the vehicle would think
it went), the mean and largest translation of a line, the lines over 3 mm
and the largest speed (m/s) with the flags it carried. --max-drift M and
--max-mean M fail (exit 1) above them. Issue 17: standing still among moving
traffic reports zero motion (docs/estimator.md, "Standing still")."""
import argparse
import csv
import math
import sys


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument('truth')
    ap.add_argument('csv')
    ap.add_argument('--max-drift', type=float)
    ap.add_argument('--max-mean', type=float)
    a = ap.parse_args()
    still = set()
    with open(a.truth) as f:
        for line in f:
            if line.startswith('#') or not line.strip():
                continue
            i, j, dx, dy, _ = line.split()
            if float(dx) == 0.0 and float(dy) == 0.0:
                still.add(int(j))
    sx = sy = total = 0.0
    n = over = 0
    worst = (0.0, 0)
    with open(a.csv) as f:
        for row in csv.DictReader(f):
            if int(row['scan']) not in still or int(row['flags']) & 0x41:  # first, recovering
                continue
            x, y = float(row['dx_m']), float(row['dy_m'])
            d = math.hypot(x, y)
            sx, sy, total, n = sx + x, sy + y, total + d, n + 1
            over += d > 0.003
            v = math.hypot(float(row['vx_mps']), float(row['vy_mps']))
            worst = max(worst, (v, int(row['flags'])))
    if n == 0:
        print('standing: no line', file=sys.stderr)
        return 1
    drift, mean = math.hypot(sx, sy), total / n
    print('standing lines %d  drift %.4f m  mean %.2f mm  max speed %.3f m/s (flags %d)  over 3 mm %d'
          % (n, drift, 1000 * mean, worst[0], worst[1], over))
    bad = (a.max_drift is not None and drift > a.max_drift) or \
          (a.max_mean is not None and mean > a.max_mean)
    return 1 if bad else 0


if __name__ == '__main__':
    sys.exit(main())
