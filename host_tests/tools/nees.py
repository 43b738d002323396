#!/usr/bin/env python3
"""nees.py TRUTH CSV: is the covariance of `lmsego replay` consistent?

TRUTH is a pairs file of lmsworld (`i j dx dy dtheta` per line, the pose of
scan j in the frame of scan i); CSV the output of `lmsego replay` (its
cov_xx .. cov_tt columns, docs/estimator.md "The covariance"). For every
line that claims a measured motion over one scan interval (flags without
first, predicted, recovering or recovered) whose covariance is known, the
normalised estimation error squared e^T C^-1 e (3 degrees of freedom: its
mean is 3 for a consistent estimate, and 1 % of the pairs lie beyond 11.34,
the 99 % ellipse) is summed apart for the lines with a part not measured
(flagged aperture or weak: a corridor's length is the prediction's) and
the others. Prints one line of each; --max-mean and --max-outside fail
(exit 1) above them (the others). --ref-sigma M,DEG adds the truth's own error (a reference that is
itself an estimate, the real logs' corrected poses: that standard deviation
in x, y and heading) to every covariance.

Silent failures (issue 16): a line that claims a motion (one interval, or a
recovered line's span from the last answered scan) whose error exceeds
--fail-m or --fail-deg (0.10 m, 1 deg) must carry a trust flag (TRUST:
aperture, low correlation, too few points, predicted, weak
rotation, translation or coupled, suspect, on objects) or a covariance whose 99.9 %
ellipse (NEES 16.27) holds the error; one that does neither is silent.
Prints their counts (and each silent pair with --list); --max-silent fails
above it. --require-flag MASK fails unless --min-share of the lines carry
one of its flags (a ring must say its turn is weak). Pure Python: no numpy."""
import argparse
import csv
import math
import sys

CHI2_3_99 = 11.345
CHI2_3_999 = 16.266
SKIP = 1 | 32 | 64 | 128  # first, predicted, recovering, recovered
FIRST, RECOVERING, RECOVERED = 1, 64, 128
# Lines with a part the scans did not measure (aperture, weak rotation,
# translation, coupled) or did on objects only: 1 m^2 or 1 rad^2 along
# it, a nearly singular covariance whose four printed digits cannot be
# inverted; counted apart.
UNMEASURED = 2 | 0x100 | 0x200 | 0x400 | 0x1000
TRUST = 2 | 8 | 16 | 32 | 0x100 | 0x200 | 0x400 | 0x800 | 0x1000


def compose(a, b):
    """Pose b (in a's frame) after a: the SE(2) product."""
    c, s = math.cos(a[2]), math.sin(a[2])
    return (a[0] + c * b[0] - s * b[1], a[1] + s * b[0] + c * b[1], a[2] + b[2])


def span(truth, i, j):
    """Scan j in the frame of scan i from the consecutive pairs, or None."""
    pose = (0.0, 0.0, 0.0)
    for k in range(i, j):
        step = truth.get((k, k + 1))
        if step is None:
            return None
        pose = compose(pose, step)
    return pose


def spans(rows):
    """(row, start, end) for each line that claims a motion: scan end in the
    frame of scan start. A recovered line's motion ends at the scan its
    search started from (the first recovering line's), and the next line's
    starts there (ego.h); first and recovering lines claim none."""
    last, target, out = None, None, []
    for r in rows:
        flags, scan = int(r['flags']), int(r['scan'])
        if flags & FIRST:
            last, target = scan, None
            continue
        if last is None:
            last = scan - 1
        if flags & RECOVERING:
            target = scan if target is None else target
            continue
        end = target if (flags & RECOVERED) and target is not None else scan
        if end > last:
            out.append((r, last, end))
        last, target = end, None
    return out


def error_of(r, t):
    return (float(r['dx_m']) - t[0], float(r['dy_m']) - t[1],
            (float(r['dtheta_rad']) - t[2] + math.pi) % (2.0 * math.pi) - math.pi)


def covariance_of(r, ref):
    """The line's covariance plus the truth's own error, or None (inf)."""
    cells = [r['cov_' + k] for k in ('xx', 'xy', 'xt', 'yy', 'yt', 'tt')]
    if any('inf' in x for x in cells):
        return None
    c = [float(x) for x in cells]
    c[0] += ref[0]
    c[3] += ref[0]
    c[5] += ref[1]
    return c


def silent_failures(truth, rows, fail_m, fail_deg, ref):
    """(failed, flagged, within the 99.9 % ellipse, [silent pairs])."""
    failed, flagged, covered, silent = 0, 0, 0, []
    for r, start, end in spans(rows):
        flags = int(r['flags'])
        t = span(truth, start, end)
        if t is None:
            continue
        e = error_of(r, t)
        if math.hypot(e[0], e[1]) <= fail_m and abs(math.degrees(e[2])) <= fail_deg:
            continue
        failed += 1
        if flags & TRUST:
            flagged += 1
            continue
        c = covariance_of(r, ref)
        n = None if c is None else nees(c, e)
        if c is None or n is None or n <= CHI2_3_999:
            covered += 1
        else:
            silent.append('%d-%d: %.3f m %.2f deg flags %d NEES %.0f' %
                          (start, end, math.hypot(e[0], e[1]), math.degrees(e[2]), flags, n))
    return failed, flagged, covered, silent


def read_truth(path):
    truth = {}
    with open(path) as f:
        for line in f:
            if line.startswith('#') or not line.strip():
                continue
            i, j, dx, dy, dt = line.split()[:5]
            truth[(int(i), int(j))] = (float(dx), float(dy), float(dt))
    return truth


def nees(c, e):
    """e^T C^-1 e for the symmetric 3x3 C given as xx, xy, xt, yy, yt, tt."""
    a = ((c[0], c[1], c[2]), (c[1], c[3], c[4]), (c[2], c[4], c[5]))
    cof = [[a[(i + 1) % 3][(j + 1) % 3] * a[(i + 2) % 3][(j + 2) % 3] -
            a[(i + 1) % 3][(j + 2) % 3] * a[(i + 2) % 3][(j + 1) % 3] for j in range(3)]
           for i in range(3)]
    det = sum(a[0][j] * cof[0][j] for j in range(3))
    if det <= 0.0:
        return None
    return sum(e[i] * cof[j][i] * e[j] for i in range(3) for j in range(3)) / det


def summary(name, values):
    if not values:
        return '%s: none' % name, 0.0, 0.0
    values = sorted(values)
    mean = sum(values) / len(values)
    outside = 100.0 * sum(1 for v in values if v > CHI2_3_99) / len(values)
    return ('%s: pairs %d  NEES mean %.2f median %.2f  beyond the 99 %% ellipse %.1f %%' %
            (name, len(values), mean, values[len(values) // 2], outside), mean, outside)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    ap.add_argument('truth')
    ap.add_argument('csv')
    ap.add_argument('--max-mean', type=float)
    ap.add_argument('--max-outside', type=float, help='percent')
    ap.add_argument('--ref-sigma', help='M,DEG: the truth\'s own standard deviation')
    ap.add_argument('--fail-m', type=float, default=0.10)
    ap.add_argument('--fail-deg', type=float, default=1.0)
    ap.add_argument('--max-silent', type=int)
    ap.add_argument('--list', action='store_true', help='print each silent failure')
    ap.add_argument('--require-flag', type=lambda x: int(x, 0),
                    help='MASK: a share of the lines (--min-share) must carry one of these flags')
    ap.add_argument('--min-share', type=float, default=0.9)
    a = ap.parse_args()
    ref = [0.0, 0.0]
    if a.ref_sigma:
        m, deg = (float(v) for v in a.ref_sigma.split(','))
        ref = [m * m, math.radians(deg) ** 2]
    truth = read_truth(a.truth)
    plain, aperture = [], []
    with open(a.csv) as f:
        rows = list(csv.DictReader(f))
    for r, start, end in spans(rows):
        flags = int(r['flags'])
        t = truth.get((start, end)) if end == start + 1 else None
        c = covariance_of(r, ref)
        if flags & SKIP or t is None or c is None:
            continue
        n = nees(c, error_of(r, t))
        if n is not None:
            (aperture if flags & UNMEASURED else plain).append(n)
    line, mean, outside = summary('measured', plain)
    print(line)
    print(summary('partly unmeasured (aperture, weak)', aperture)[0])
    bad, flagged, covered, silent = silent_failures(truth, rows, a.fail_m, a.fail_deg, ref)
    print('failures (> %.2f m or %.1f deg): %d, flagged %d, within the 99.9 %% ellipse %d, '
          'silent %d of %d lines' % (a.fail_m, a.fail_deg, bad, flagged, covered, len(silent), len(rows)))
    for line in silent if a.list else []:
        print('  silent ' + line)
    flagged_share = 1.0
    if a.require_flag is not None:
        with_flag = sum(1 for r in rows if int(r['flags']) & a.require_flag)
        flagged_share = with_flag / len(rows) if rows else 0.0
        print('lines with flags 0x%x: %d of %d' % (a.require_flag, with_flag, len(rows)))
    failed = ((a.require_flag is not None and flagged_share < a.min_share) or
              (a.max_mean is not None and mean > a.max_mean) or
              (a.max_outside is not None and outside > a.max_outside) or
              (a.max_silent is not None and len(silent) > a.max_silent))
    if failed:
        print('BOUND EXCEEDED', file=sys.stderr)
        return 1
    return 0


if __name__ == '__main__':
    sys.exit(main())
