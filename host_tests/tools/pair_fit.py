#!/usr/bin/python3
"""Which pose fits a scan pair better: the reference or an estimate?

usage: pair_fit.py LOG EST [--pairs I,I,...] [--failed-only] [--shared-tools DIR]

For each consecutive pair (i, i+1) of a CARMEN log, places scan i+1 in the
frame of scan i by the reference relative pose (the corrected poses) and by
the estimate from EST (`i j dx dy dtheta` lines), and scores both the same
way: every point of scan i+1 (no-return and > 30 m readings dropped) gets
its distance to the nearest segment of scan i (neighbouring points joined
unless they are more than max(0.3 m, 4 r dphi) apart), truncated at 0.2 m;
the score is the mean squared truncated distance (lower is better). A
failed pair (0.10 m / 2 deg) whose estimate fits clearly better than the
reference (score below 0.8 x the reference's) is more likely a reference
error than a matching error. Independent of the estimator's own code.
Needs Debian's python3-numpy.
"""
import argparse
import math
import os
import sys

import numpy as np

TRUNC = 0.20
# The median translation target; a pair off by more than this whose
# estimate fits the scans better says the median is limited by the reference.
MEDIAN_TARGET = 0.025


def load_est(path):
    est = {}
    with open(path) as f:
        for line in f:
            if not line.strip() or line.startswith('#'):
                continue
            a = line.split()
            est[(int(a[0]), int(a[1]))] = (float(a[2]), float(a[3]), float(a[4]))
    return est


def points(scan, no_return):
    r = np.array(scan.ranges)
    a = np.array(scan.angles())
    keep = (r < no_return - 1e-6) & (r <= 30.0)
    return r[keep], np.c_[r[keep] * np.cos(a[keep]), r[keep] * np.sin(a[keep])], scan.angle_inc


def segments(r, p, inc):
    d = np.hypot(*(p[1:] - p[:-1]).T)
    limit = np.maximum(0.3, 4.0 * np.minimum(r[1:], r[:-1]) * abs(inc))
    join = d <= limit
    return p[:-1][join], p[1:][join], p


def score(seg, q):
    a, b, lone = seg
    best = np.full(len(q), TRUNC * TRUNC)
    if len(lone):
        d2 = ((q[:, None, :] - lone[None, :, :]) ** 2).sum(-1).min(1)
        best = np.minimum(best, d2)
    if len(a):
        ab = b - a
        L = (ab ** 2).sum(1)
        t = ((q[:, None, :] - a[None]) * ab[None]).sum(-1) / np.maximum(L, 1e-12)[None]
        t = np.clip(t, 0.0, 1.0)
        c = a[None] + t[..., None] * ab[None]
        best = np.minimum(best, ((q[:, None, :] - c) ** 2).sum(-1).min(1))
    return float(best.mean())


def place(p, pose):
    c, s = math.cos(pose[2]), math.sin(pose[2])
    return np.c_[pose[0] + c * p[:, 0] - s * p[:, 1], pose[1] + s * p[:, 0] + c * p[:, 1]]


def main():
    here = os.path.dirname(os.path.abspath(__file__))
    ap = argparse.ArgumentParser()
    ap.add_argument('log')
    ap.add_argument('est')
    ap.add_argument('--pairs', help='comma-separated i of the pairs (i, i+1) to score')
    ap.add_argument('--failed-only', action='store_true')
    ap.add_argument('--shared-tools', default=os.path.join(here, '../../../shared/tools'))
    a = ap.parse_args()
    sys.path.insert(0, a.shared_tools)
    try:
        import carmenlog
        log = carmenlog.read_log(a.log)
        est = load_est(a.est)
    except (ImportError, OSError, ValueError) as e:
        print('pair_fit.py: %s' % e, file=sys.stderr)
        return 2
    nr = carmenlog.no_return_threshold(log)
    wanted = [int(x) for x in a.pairs.split(',')] if a.pairs else range(len(log.scans) - 1)
    n = failed = ref_worse = 0
    off = off_better = 0  # pairs off by more than MEDIAN_TARGET, and how many fit the estimate better
    for i in wanted:
        if (i, i + 1) not in est:
            continue
        ref = carmenlog.reference_relpose(log, i, i + 1)
        e = est[(i, i + 1)]
        terr = math.hypot(e[0] - ref[0], e[1] - ref[1])
        rerr = abs(math.degrees(math.remainder(e[2] - ref[2], 2 * math.pi)))
        fail = terr > 0.10 or rerr > 2.0
        if a.failed_only and not fail:
            continue
        r0, p0, inc = points(log.scans[i], nr)
        _, p1, _ = points(log.scans[i + 1], nr)
        seg = segments(r0, p0, inc)
        s_ref = score(seg, place(p1, ref))
        s_est = score(seg, place(p1, e))
        n += 1
        failed += fail
        if terr > MEDIAN_TARGET:
            off += 1
            off_better += s_est < s_ref
        verdict = ''
        if fail and s_est < 0.8 * s_ref:
            verdict = 'estimate fits better: reference suspect'
            ref_worse += 1
        print('%d %d terr %.3f rerr %.2f fail %d score_ref %.5f score_est %.5f %s' %
              (i, i + 1, terr, rerr, fail, s_ref, s_est, verdict))
    print('# pairs %d failed %d of which the estimate fits clearly better: %d' %
          (n, failed, ref_worse))
    print('# pairs off by more than %.3f m: %d, of which the estimate fits better: %d' %
          (MEDIAN_TARGET, off, off_better))
    return 0


if __name__ == '__main__':
    sys.exit(main())
