#!/usr/bin/env python3
"""Compare `lmsego replay` CSV with a ground-truth pairs file (lmsworld).

usage: pairs_error.py TRUTH.pairs REPLAY.csv [--exclude-flags MASK] [--fail-m 0.10 --fail-deg 1.0]
                     [--max-failed N] [--min-failed N] [--max-rot-mean DEG] [--max-trans-mean M]
                     [--max-rot-median DEG] [--max-trans-median M]

Prints, over the pairs present in both: translation error (along = x of the
truth's frame, across = y) and rotation error: mean, median, p95, max; and the
failure count (translation error > fail-m or rotation error > fail-deg, or no
answer).

A line's pose is compared with the truth over the span it covers (the
estimator's flags, estimator/ego.h): a line flagged 64 (recovering) claims
no motion and counts as a failed pair; the search it belongs to started at
the first line of its run of 64s; the line flagged 128 (recovered) gives
the motion from the last answered scan to that one, and the next line the
motion from there to its own scan. Truth over a span is the consecutive
truth pairs composed. A line flagged 1 (first) answers nothing and restarts. With --max-* bounds it exits 1 when one is exceeded (ctest uses
that), else 0. Standard library only.
"""
import argparse
import math
import signal
import statistics
import sys


def read_truth(path):
    truth = {}
    with open(path) as f:
        for line in f:
            if not line.strip() or line.startswith('#'):
                continue
            i, j, dx, dy, dt = line.split()
            truth[int(j)] = (float(dx), float(dy), float(dt))
    return truth


def read_csv(path):
    """The lines in scan order: (scan, dx, dy, dtheta, flags)."""
    lines = []
    with open(path) as f:
        header = f.readline().strip().split(',')
        col = {name: k for k, name in enumerate(header)}
        for line in f:
            v = line.strip().split(',')
            if len(v) != len(header):
                continue
            lines.append((int(v[col['scan']]), float(v[col['dx_m']]), float(v[col['dy_m']]),
                          float(v[col['dtheta_rad']]), int(v[col['flags']])))
    return lines


FLAG_FIRST = 1
FLAG_RECOVERING = 64
FLAG_RECOVERED = 128


def compose(a, b):
    """Pose b (in a's end frame) after pose a: (dx, dy, dtheta)."""
    c, s = math.cos(a[2]), math.sin(a[2])
    return (a[0] + c * b[0] - s * b[1], a[1] + s * b[0] + c * b[1], a[2] + b[2])


def truth_span(truth, i, j):
    """Truth from scan i to scan j (i < j), or None where a pair is missing."""
    pose = (0.0, 0.0, 0.0)
    for k in range(i + 1, j + 1):
        if k not in truth:
            return None
        pose = compose(pose, truth[k])
    return pose


def answers(truth, lines):
    """(truth pose, estimate, flags) per answered span; and the unanswered
    scans (recovering, first, or missing)."""
    out = []
    unanswered = set(truth)
    ref = None      # the scan the next motion starts from
    target = None   # the scan a running search started from
    for scan, dx, dy, dt, flags in lines:
        if flags & FLAG_FIRST:
            ref, target = scan, None
            continue
        if ref is None:
            ref = scan - 1
        if flags & FLAG_RECOVERING:
            if target is None:
                target = scan
            continue
        end = scan
        if flags & FLAG_RECOVERED and target is not None:
            end = target
        t = truth_span(truth, ref, end) if end > ref else None
        if t is not None:
            out.append((t, (dx, dy, dt), flags))
            if end == scan:
                unanswered.discard(scan)
            else:
                unanswered.discard(end)
        ref, target = end, None
    return out, unanswered


def stats(values):
    if not values:
        return 'n=0'
    s = sorted(values)
    p95 = s[min(len(s) - 1, int(math.ceil(0.95 * len(s))) - 1)]
    sd = statistics.pstdev(s) if len(s) > 1 else 0.0
    return 'mean %.6f std %.6f median %.6f p95 %.6f max %.6f' % (
        statistics.fmean(s), sd, statistics.median(s), p95, s[-1])


def main():
    signal.signal(signal.SIGPIPE, signal.SIG_DFL)  # quiet when piped into head
    ap = argparse.ArgumentParser()
    ap.add_argument('truth')
    ap.add_argument('csv')
    ap.add_argument('--exclude-flags', type=lambda x: int(x, 0), default=0,
                    help='leave pairs with any of these flags out of the translation figures '
                         'and the translation failures (2 = aperture, as the paper does)')
    ap.add_argument('--fail-m', type=float, default=0.10)
    ap.add_argument('--fail-deg', type=float, default=1.0)
    ap.add_argument('--max-failed', type=int)
    ap.add_argument('--min-failed', type=int, help='fail unless at least this many pairs failed '
                                                   '(a test that a setting matters)')
    ap.add_argument('--max-rot-mean', type=float)
    ap.add_argument('--max-trans-mean', type=float)
    ap.add_argument('--max-rot-median', type=float)
    ap.add_argument('--max-trans-median', type=float)
    a = ap.parse_args()
    truth = read_truth(a.truth)
    spans, unanswered = answers(truth, read_csv(a.csv))
    along, across, trans, rot = [], [], [], []
    fails = len(unanswered)
    for (tx, ty, tt), (ex, ey, et), flags in spans:
        r = abs(math.degrees(math.remainder(et - tt, 2 * math.pi)))
        rot.append(r)
        t = math.hypot(ex - tx, ey - ty)
        excluded = bool(flags & a.exclude_flags)
        if r > a.fail_deg or (t > a.fail_m and not excluded):
            fails += 1
        if excluded:
            continue
        trans.append(t)
        along.append(abs(ex - tx))
        across.append(abs(ey - ty))
    print('pairs %d  failed %d (%.1f %%)  translation excluded %d  unanswered %d  spans %d' % (
        len(truth), fails, 100.0 * fails / max(1, len(truth)), len(rot) - len(trans),
        len(unanswered), len(spans)))
    print('rotation deg   ' + stats(rot))
    print('translation m  ' + stats(trans))
    print('along m        ' + stats(along))
    print('across m       ' + stats(across))
    broken = []
    if a.max_failed is not None and fails > a.max_failed:
        broken.append('failed %d > %d' % (fails, a.max_failed))
    if a.min_failed is not None and fails < a.min_failed:
        broken.append('failed %d < %d' % (fails, a.min_failed))
    if a.max_rot_mean is not None and (not rot or statistics.fmean(rot) > a.max_rot_mean):
        broken.append('rotation mean above %g deg' % a.max_rot_mean)
    if a.max_trans_mean is not None and (not trans or statistics.fmean(trans) > a.max_trans_mean):
        broken.append('translation mean above %g m' % a.max_trans_mean)
    if a.max_rot_median is not None and (not rot or statistics.median(rot) > a.max_rot_median):
        broken.append('rotation median above %g deg' % a.max_rot_median)
    if a.max_trans_median is not None and (not trans or
                                           statistics.median(trans) > a.max_trans_median):
        broken.append('translation median above %g m' % a.max_trans_median)
    for b in broken:
        print('BOUND EXCEEDED: ' + b)
    return 1 if broken else 0


if __name__ == '__main__':
    sys.exit(main())
