#!/usr/bin/env python3
"""Score `lmsego replay --objects` against lmsworld's moving-object truth.

usage: objects_score.py TRUTH.objects OURS.csv [--from K] [--range 30] [--min-returns 5]
                        [--gate 1.5] [--min-detected F] [--min-pedestrians F] [--max-false F]
                        [--max-vel-median V]

TRUTH.objects: `scan id cx cy heading vx vy length width returns` (lmsworld
--objects; docs/synthetic-worlds.md). OURS.csv: the header
`scan,id,cx_m,cy_m,length_m,width_m,vx_mps,vy_mps,points`, then one line per
object and scan (vx, vy may be nan).

Per scan from K on (default 0; the detector needs a reference scan 0.2 s
back and three sightings, so the first ~0.25 s of a sequence cannot have
objects): the targets are the truth objects with at least --min-returns
beams on them whose centre lies within --range metres of the scanner.
Vehicles (length >= 2 m) and pedestrians are counted apart, and so are
the truth objects standing still (speed over ground below --min-speed,
0.5 m/s: a queue's waiting cars), which a detector of motion cannot see:
the shares are over the moving targets, and a report on a standing one is
not false either. Ours sees only
the sides facing the scanner, so a report matches a truth object when its
centre lies within --gate metres of the truth's rectangle (0 inside it),
not of the rectangle's centre. Pairs are taken nearest first, one report
per truth object; a report matched to no target but within the gate of
another truth object (fewer returns, further away) is not false, nor is a
second report on a matched object (counted as split). False: a report
within the gate of no truth object.

Prints: targets and the share detected (vehicles, pedestrians), false
reports per scan, split reports, and the velocity error |v_ours - v_truth|
(m/s, the vector difference; mean, median, p90) over the matched targets
whose report has a velocity. With the --min/--max bounds it exits 1 when
one is missed (ctest uses that). Standard library only.
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
            v = line.split()
            scan, oid = int(v[0]), int(v[1])
            cx, cy, heading, vx, vy, length, width = (float(x) for x in v[2:9])
            truth.setdefault(scan, []).append(
                dict(id=oid, cx=cx, cy=cy, h=heading, vx=vx, vy=vy, l=length, w=width,
                     returns=int(v[9])))
    return truth


COLUMNS = 'scan,id,cx_m,cy_m,length_m,width_m,vx_mps,vy_mps,points'


def read_ours(path):
    ours = {}
    with open(path) as f:
        header = f.readline().strip()
        if header != COLUMNS:
            sys.exit(f'objects_score: {path}: header is not {COLUMNS!r}')
        for line in f:
            v = line.strip().split(',')
            if len(v) != 9:
                sys.exit(f'objects_score: {path}: bad line {line.strip()!r}')
            ours.setdefault(int(v[0]), []).append(
                dict(id=int(v[1]), cx=float(v[2]), cy=float(v[3]), vx=float(v[6]),
                     vy=float(v[7]), points=int(v[8])))
    return ours


def box_distance(t, x, y):
    """Distance from (x, y) to the truth rectangle (0 inside)."""
    c, s = math.cos(t['h']), math.sin(t['h'])
    u = c * (x - t['cx']) + s * (y - t['cy'])
    v = -s * (x - t['cx']) + c * (y - t['cy'])
    du = max(abs(u) - t['l'] / 2, 0.0)
    dv = max(abs(v) - t['w'] / 2, 0.0)
    return math.hypot(du, dv)


def main():
    signal.signal(signal.SIGPIPE, signal.SIG_DFL)
    ap = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    ap.add_argument('truth')
    ap.add_argument('ours')
    ap.add_argument('--from', dest='first', type=int, default=0)
    ap.add_argument('--range', type=float, default=30.0)
    ap.add_argument('--min-returns', type=int, default=5)
    ap.add_argument('--gate', type=float, default=1.5)
    ap.add_argument('--min-speed', type=float, default=0.5)
    ap.add_argument('--min-detected', type=float)
    ap.add_argument('--min-pedestrians', type=float)
    ap.add_argument('--max-false', type=float)
    ap.add_argument('--max-vel-median', type=float)
    a = ap.parse_args()
    truth = read_truth(a.truth)
    ours = read_ours(a.ours)
    scans = [s for s in sorted(truth) if s >= a.first and s > 0]
    targets = {'vehicle': 0, 'pedestrian': 0}
    standing = 0
    detected = {'vehicle': 0, 'pedestrian': 0}
    false = 0
    split = 0
    vel_err = []
    for s in scans:
        objs = truth[s]
        reps = ours.get(s, [])
        pairs = sorted((box_distance(t, r['cx'], r['cy']), ti, ri)
                       for ti, t in enumerate(objs) for ri, r in enumerate(reps))
        seen = [t['returns'] >= a.min_returns and math.hypot(t['cx'], t['cy']) <= a.range
                for t in objs]
        is_target = [seen[i] and math.hypot(t['vx'], t['vy']) >= a.min_speed
                     for i, t in enumerate(objs)]
        standing += sum(1 for i in range(len(objs)) if seen[i] and not is_target[i])
        t_used, r_used = set(), set()
        for d, ti, ri in pairs:
            if d > a.gate or ti in t_used or ri in r_used:
                continue
            t_used.add(ti)
            r_used.add(ri)
            if is_target[ti]:
                t = objs[ti]
                kind = 'vehicle' if t['l'] >= 2.0 else 'pedestrian'
                detected[kind] += 1
                r = reps[ri]
                if math.isfinite(r['vx']) and math.isfinite(r['vy']):
                    vel_err.append(math.hypot(r['vx'] - t['vx'], r['vy'] - t['vy']))
        for ti, t in enumerate(objs):
            if is_target[ti]:
                targets['vehicle' if t['l'] >= 2.0 else 'pedestrian'] += 1
        for ri, r in enumerate(reps):
            if ri in r_used:
                continue
            if any(box_distance(t, r['cx'], r['cy']) <= a.gate for t in objs):
                split += 1
            else:
                false += 1
    n = max(len(scans), 1)
    ok = True
    total = targets['vehicle'] + targets['pedestrian']
    print(f'scans {len(scans)} (from {a.first}); targets: within {a.range:g} m, '
          f'>= {a.min_returns} returns, >= {a.min_speed:g} m/s; gate {a.gate:g} m to the truth box;'
          f' {standing} more standing still')
    share = {}
    for kind in ('vehicle', 'pedestrian'):
        share[kind] = detected[kind] / targets[kind] if targets[kind] else float('nan')
        print(f'{kind}s: {targets[kind]} targets, {detected[kind]} detected, '
              f'share {share[kind]:.3f}')
    all_share = (detected['vehicle'] + detected['pedestrian']) / total if total else float('nan')
    print(f'false {false} ({false / n:.3f} per scan), split {split} ({split / n:.3f} per scan)')
    if vel_err:
        vel_err.sort()
        p90 = vel_err[min(len(vel_err) - 1, int(0.9 * len(vel_err)))]
        print(f'velocity error m/s over {len(vel_err)} matched with a velocity: '
              f'mean {statistics.mean(vel_err):.3f} median {statistics.median(vel_err):.3f} '
              f'p90 {p90:.3f}')
    else:
        print('velocity error m/s over 0 matched with a velocity')
    print(f'summary vehicles {share["vehicle"]:.3f} all {all_share:.3f} '
          f'false_per_scan {false / n:.3f} '
          f'vel_median {statistics.median(vel_err) if vel_err else float("nan"):.3f} '
          f'vel_mean {statistics.mean(vel_err) if vel_err else float("nan"):.3f}')
    if a.min_detected is not None and not share['vehicle'] >= a.min_detected:
        print(f'FAIL: vehicle share {share["vehicle"]:.3f} < {a.min_detected}')
        ok = False
    if a.min_pedestrians is not None and not share['pedestrian'] >= a.min_pedestrians:
        print(f'FAIL: pedestrian share {share["pedestrian"]:.3f} < {a.min_pedestrians}')
        ok = False
    if a.max_false is not None and false / n > a.max_false:
        print(f'FAIL: false per scan {false / n:.3f} > {a.max_false}')
        ok = False
    if a.max_vel_median is not None and not (vel_err and statistics.median(vel_err)
                                             <= a.max_vel_median):
        print(f'FAIL: velocity median above {a.max_vel_median}')
        ok = False
    return 0 if ok else 1


if __name__ == '__main__':
    sys.exit(main())
