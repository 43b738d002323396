#!/usr/bin/env python3
"""scaled_prior.py PAIRS SCALE OUT: an odometry-like prior from a truth file.

Each line 'i j dx dy dtheta' of PAIRS (the truth, pose of scan j in the
frame of scan i) is written to OUT with its translation times SCALE: a
wheel odometry whose tyre radius is SCALE times the one it assumes (issue
17: behind a platoon the prior keeps the static world apart from trucks
moving with us, within odometry's error). Comment lines are copied."""
import sys


def main():
    if len(sys.argv) != 4:
        print('usage: scaled_prior.py PAIRS SCALE OUT', file=sys.stderr)
        return 2
    scale = float(sys.argv[2])
    with open(sys.argv[1]) as src, open(sys.argv[3], 'w') as out:
        for line in src:
            f = line.split()
            if line.startswith('#') or len(f) != 5:
                out.write(line)
                continue
            out.write('%s %s %.9f %.9f %s\n' % (f[0], f[1], float(f[2]) * scale,
                                                 float(f[3]) * scale, f[4]))
    return 0


if __name__ == '__main__':
    sys.exit(main())
