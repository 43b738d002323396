#!/usr/bin/python3
"""Plot scan-to-scan relative-pose estimates against a CARMEN log's corrected poses.

usage:
  plot_relpose.py LOG EST [EST2 ...] --out-prefix PREFIX [--label L ...]
                  [--failed-pair I] [--title T] [--shared-tools DIR] [--dpi N]

LOG   CARMEN log (.log or .log.gz); its scans' corrected laser poses are the
      reference (read with carmenlog.py from the shared tools directory).
EST   estimate file ("pairs" format): lines  i j dx dy dtheta  (scan numbers;
      metres, radians: the pose of scan j in the frame of scan i); '#' starts
      a comment.  Only consecutive pairs (j = i + 1) are used; other lines are
      counted and reported on stderr.

Per pair: t_ref = translation of between(P_i, P_j),
  trans_err = || t_est - t_ref ||,  rot_err = | wrap(dtheta_est - dtheta_ref) |.
A pair fails if trans_err > 0.10 m or rot_err > 2 deg; a missing pair also
fails (the same rules as relpose_eval.py, stride 1, whose numbers the summary
lines printed here must match).

Writes
  PREFIX-trajectory.png  each EST's consecutive pairs composed from scan 0's
                         reference pose (a missing pair is composed as the
                         identity, and the count is given in the legend),
                         against the reference trajectory.
  PREFIX-errors.png      translation / rotation error per pair (x = scan i),
                         one line per EST, failure thresholds dashed.
  PREFIX-pair-I.png      scans I (blue) and I+1 (red), the second placed by the
                         reference relative pose (left) and by the first EST
                         (right).  I is --failed-pair, or by default the failed
                         pair of the first EST with the largest translation
                         error (no such plot if the first EST has no failed
                         pair with an estimate).  Ranges >= the log's no-return
                         value, > 30 m or <= 0 are not drawn.
and prints one summary line per EST.

Exit status: 0 on success, 2 on bad arguments, missing or unreadable input.
Needs numpy and matplotlib (Debian's /usr/bin/python3 has both).
"""

import argparse
import importlib.util
import math
import os
import sys

TRANS_FAIL_M = 0.10
ROT_FAIL_DEG = 2.0
MAX_PLOT_RANGE_M = 30.0
ERR_FLOOR = 1e-5   # errors are drawn at least this big on the log axes


class UsageError(Exception):
    """A problem with the arguments or the input files: message, exit 2."""


class Parser(argparse.ArgumentParser):
    def error(self, message):
        self.print_usage(sys.stderr)
        raise UsageError(message)


def default_shared_tools():
    here = os.path.dirname(os.path.abspath(__file__))
    return os.path.normpath(os.path.join(here, "..", "..", "..", "shared", "tools"))


def load_carmenlog(tools_dir):
    path = os.path.join(tools_dir, "carmenlog.py")
    if not os.path.isfile(path):
        raise UsageError("carmenlog.py not found in shared tools directory '%s' (use --shared-tools DIR)"
                         % tools_dir)
    spec = importlib.util.spec_from_file_location("carmenlog", path)
    mod = importlib.util.module_from_spec(spec)
    try:
        spec.loader.exec_module(mod)
    except Exception as e:  # a broken module file: report it, no traceback
        raise UsageError("cannot load %s: %s" % (path, e))
    for name in ("read_log", "between", "wrap", "compose", "reference_relpose", "no_return_threshold"):
        if not hasattr(mod, name):
            raise UsageError("%s has no '%s'; is it the right carmenlog.py?" % (path, name))
    return mod


def read_estimates(path):
    """{(i, j): (dx, dy, dtheta)} of a pairs file; UsageError when unreadable."""
    if not os.path.exists(path):
        raise UsageError("estimate file '%s' does not exist" % path)
    est = {}
    duplicates = 0
    try:
        with open(path, "r") as f:
            for line_no, line in enumerate(f, 1):
                text = line.split("#", 1)[0].strip()
                if not text:
                    continue
                tok = text.split()
                if len(tok) != 5:
                    raise UsageError("%s:%d: expected 5 fields 'i j dx dy dtheta', got %d"
                                     % (path, line_no, len(tok)))
                try:
                    i, j = int(tok[0]), int(tok[1])
                    pose = (float(tok[2]), float(tok[3]), float(tok[4]))
                except ValueError:
                    raise UsageError("%s:%d: not a pair line (i j dx dy dtheta): %r"
                                     % (path, line_no, text))
                if not all(math.isfinite(v) for v in pose):
                    raise UsageError("%s:%d: non-finite value: %r" % (path, line_no, text))
                if (i, j) in est:
                    duplicates += 1
                est[(i, j)] = pose
    except UnicodeDecodeError:
        raise UsageError("estimate file '%s' is not a text file" % path)
    except OSError as e:
        raise UsageError("cannot read estimate file '%s': %s" % (path, e.strerror or e))
    if not est:
        raise UsageError("estimate file '%s' contains no pair lines" % path)
    if duplicates:
        print("note: %s: %d pair(s) given more than once, the last line is used" % (path, duplicates),
              file=sys.stderr)
    return est


def evaluate(C, log, est):
    """Errors of the consecutive pairs; arrays indexed by i (nan where missing)."""
    import numpy as np
    n = len(log.scans)
    te = np.full(n - 1, np.nan)
    re_ = np.full(n - 1, np.nan)
    for i in range(n - 1):
        e = est.get((i, i + 1))
        if e is None:
            continue
        ref = C.reference_relpose(log, i, i + 1)
        te[i] = math.hypot(e[0] - ref[0], e[1] - ref[1])
        re_[i] = abs(math.degrees(C.wrap(e[2] - ref[2])))
    present = ~np.isnan(te)
    failed = ~present | (np.where(present, te, 0.0) > TRANS_FAIL_M) | (np.where(present, re_, 0.0) > ROT_FAIL_DEG)
    return te, re_, failed


def integrate(C, log, est):
    """Trajectory of the composed consecutive pairs from scan 0's reference pose."""
    pose = tuple(log.scans[0].pose)
    xs, ys = [pose[0]], [pose[1]]
    missing = 0
    for i in range(len(log.scans) - 1):
        step = est.get((i, i + 1))
        if step is None:
            missing += 1
            step = (0.0, 0.0, 0.0)
        pose = C.compose(pose, step)
        xs.append(pose[0])
        ys.append(pose[1])
    return xs, ys, missing


def scan_points(scan, max_valid):
    import numpy as np
    r = np.asarray(scan.ranges, dtype=float)
    a = np.asarray(scan.angles(), dtype=float)
    keep = (r > 0.0) & (r < max_valid) & (r <= MAX_PLOT_RANGE_M)
    r, a = r[keep], a[keep]
    return r * np.cos(a), r * np.sin(a)


def place(xs, ys, pose):
    import numpy as np
    c, s = math.cos(pose[2]), math.sin(pose[2])
    return pose[0] + c * xs - s * ys, pose[1] + s * xs + c * ys


def fmt_pose(p):
    return "dx %.3f m, dy %.3f m, d$\\theta$ %.2f$\\degree$" % (p[0], p[1], math.degrees(p[2]))


def plot_trajectory(plt, C, log, ests, labels, failed_pair, title, out, dpi):
    fig, ax = plt.subplots(figsize=(6.4, 6.0))
    rx = [s.pose[0] for s in log.scans]
    ry = [s.pose[1] for s in log.scans]
    ax.plot(rx, ry, color="black", lw=2.2, alpha=0.35, label="reference (corrected poses)")
    colors = plt.rcParams["axes.prop_cycle"].by_key()["color"]
    for k, (est, label) in enumerate(zip(ests, labels)):
        xs, ys, missing = integrate(C, log, est)
        if missing:
            label = "%s (%d missing pair%s composed as identity)" % (label, missing, "" if missing == 1 else "s")
        ax.plot(xs, ys, lw=1.0, color=colors[k % len(colors)], label=label)
    ax.plot([rx[0]], [ry[0]], "o", color="black", ms=6, label="start (scan 0)")
    if failed_pair is not None:
        ax.plot([rx[failed_pair]], [ry[failed_pair]], "x", color="magenta", ms=9, mew=2,
                label="pair %d-%d (plotted)" % (failed_pair, failed_pair + 1))
    ax.set_aspect("equal", adjustable="datalim")
    ax.set_xlabel("x (m)")
    ax.set_ylabel("y (m)")
    ax.set_title("%s: integrated consecutive pairs" % title)
    ax.grid(True, alpha=0.3)
    ax.legend(loc="best", fontsize=8, framealpha=0.85)
    fig.tight_layout()
    fig.savefig(out, dpi=dpi)
    plt.close(fig)


def plot_errors(plt, results, labels, failed_pair, title, out, dpi):
    import numpy as np
    fig, (at, ar) = plt.subplots(2, 1, figsize=(8.0, 5.6), sharex=True)
    colors = plt.rcParams["axes.prop_cycle"].by_key()["color"]
    for k, ((te, re_, failed), label) in enumerate(zip(results, labels)):
        x = np.arange(len(te))
        c = colors[k % len(colors)]
        lab = "%s (%d failed)" % (label, int(failed.sum()))
        at.plot(x, np.maximum(te, ERR_FLOOR), lw=0.8, color=c, alpha=0.85, label=lab)
        ar.plot(x, np.maximum(re_, ERR_FLOOR), lw=0.8, color=c, alpha=0.85, label=lab)
        miss = np.isnan(te)
        if miss.any():
            at.plot(x[miss], np.full(miss.sum(), 3.0), "v", color=c, ms=4, label="%s: missing" % label)
    at.axhline(TRANS_FAIL_M, color="red", ls="--", lw=1.0, label="fail > %.2f m" % TRANS_FAIL_M)
    ar.axhline(ROT_FAIL_DEG, color="red", ls="--", lw=1.0, label="fail > %g deg" % ROT_FAIL_DEG)
    for ax in (at, ar):
        ax.set_yscale("log")
        ax.grid(True, which="major", alpha=0.3)
        if failed_pair is not None:
            ax.axvline(failed_pair, color="magenta", ls=":", lw=1.0)
        ax.legend(loc="upper right", fontsize=7, framealpha=0.85, ncol=2)
    at.set_ylabel("translation error (m)")
    ar.set_ylabel("rotation error (deg)")
    ar.set_xlabel("scan i (pair i, i+1)")
    at.set_title("%s: per-pair error against the corrected poses" % title)
    fig.tight_layout()
    fig.savefig(out, dpi=dpi)
    plt.close(fig)


def plot_pair(plt, C, log, est, label, result, i, title, out, dpi):
    import numpy as np
    nr = C.no_return_threshold(log)
    ax0, ay0 = scan_points(log.scans[i], nr)
    bx, by = scan_points(log.scans[i + 1], nr)
    ref = C.reference_relpose(log, i, i + 1)
    e = est.get((i, i + 1))
    fig, axes = plt.subplots(1, 2, figsize=(10.0, 5.2))
    # common limits, so that both panels show the same region at the same scale
    allx, ally = [ax0, [0.0]], [ay0, [0.0]]
    for pose in (ref, e):
        if pose is not None:
            px, py = place(bx, by, pose)
            allx += [px, [pose[0]]]
            ally += [py, [pose[1]]]
    allx, ally = np.concatenate(allx), np.concatenate(ally)
    padx = 0.04 * max(allx.max() - allx.min(), 1.0)
    pady = 0.04 * max(ally.max() - ally.min(), 1.0)
    xlim = [allx.min() - padx, allx.max() + padx]
    ylim = [ally.min() - pady, ally.max() + pady]
    # keep the panels from getting very flat or very tall: height/width in [0.7, 1.1]
    w, h = xlim[1] - xlim[0], ylim[1] - ylim[0]
    if h < 0.7 * w:
        grow, lim = 0.5 * (0.7 * w - h), ylim
    elif h > 1.1 * w:
        grow, lim = 0.5 * (h / 1.1 - w), xlim
    else:
        grow, lim = 0.0, xlim
    lim[0] -= grow
    lim[1] += grow
    panels = [(axes[0], ref, "reference: " + fmt_pose(ref)), (axes[1], e, None)]
    te, re_, failed = result
    for ax, pose, head in panels:
        ax.plot(ax0, ay0, ".", color="tab:blue", ms=2.5, label="scan %d" % i)
        ax.plot([0.0], [0.0], "^", color="tab:blue", ms=7)
        if pose is not None:
            px, py = place(bx, by, pose)
            ax.plot(px, py, ".", color="tab:red", ms=2.5, label="scan %d" % (i + 1))
            ax.plot([pose[0]], [pose[1]], "^", color="tab:red", ms=7)
            ax.annotate("", xy=(pose[0] + 0.8 * math.cos(pose[2]), pose[1] + 0.8 * math.sin(pose[2])),
                        xytext=(pose[0], pose[1]), arrowprops=dict(arrowstyle="->", color="tab:red"))
        ax.annotate("", xy=(0.8, 0.0), xytext=(0.0, 0.0), arrowprops=dict(arrowstyle="->", color="tab:blue"))
        if head is None:
            if pose is None:
                head = "%s: no estimate for this pair" % label
                ax.text(0.5, 0.5, "no estimate", transform=ax.transAxes, ha="center", fontsize=14)
            else:
                head = ("%s: %s\nerror: %.3f m, %.2f$\\degree$%s"
                        % (label, fmt_pose(pose), te[i], re_[i], "  (FAILED)" if failed[i] else ""))
        ax.set_title(head, fontsize=9)
        ax.set_xlim(*xlim)
        ax.set_ylim(*ylim)
        ax.set_aspect("equal", adjustable="box")
        ax.set_xlabel("x in frame of scan %d (m)" % i)
        ax.grid(True, alpha=0.3)
        ax.legend(loc="best", fontsize=8, markerscale=3)
    axes[0].set_ylabel("y (m)")
    fig.suptitle("%s: pair %d-%d" % (title, i, i + 1), fontsize=11)
    fig.tight_layout()
    fig.savefig(out, dpi=dpi)
    plt.close(fig)


def main(argv=None):
    ap = Parser(description="Plot scan-to-scan relative-pose estimates against a CARMEN log "
                            "(see the module docstring for details).")
    ap.add_argument("log", help="CARMEN log (.log or .log.gz)")
    ap.add_argument("est", nargs="+", help="estimate files (i j dx dy dtheta)")
    ap.add_argument("--out-prefix", required=True, help="output file prefix (PREFIX-trajectory.png, ...)")
    ap.add_argument("--label", action="append", default=[], help="label of each EST, in order (repeat)")
    ap.add_argument("--failed-pair", type=int, metavar="I", help="pair I, I+1 to plot (default: worst failure)")
    ap.add_argument("--title", help="figure title prefix (default: log file name)")
    ap.add_argument("--shared-tools", default=default_shared_tools(), metavar="DIR",
                    help="directory holding carmenlog.py (default: %(default)s)")
    ap.add_argument("--dpi", type=float, default=80.0, help="image resolution (default 80)")
    a = ap.parse_intermixed_args(argv)

    if a.label and len(a.label) != len(a.est):
        raise UsageError("%d --label given for %d estimate files" % (len(a.label), len(a.est)))
    if not (10.0 <= a.dpi <= 600.0):
        raise UsageError("--dpi must be between 10 and 600")
    out_dir = os.path.dirname(os.path.abspath(a.out_prefix))
    if not os.path.isdir(out_dir):
        raise UsageError("output directory '%s' does not exist" % out_dir)
    if not os.path.isfile(a.log):
        raise UsageError("log file '%s' does not exist" % a.log)

    C = load_carmenlog(a.shared_tools)
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        import numpy  # noqa: F401
    except ImportError as e:
        raise UsageError("needs numpy and matplotlib (%s); run with /usr/bin/python3" % e)

    ests = [read_estimates(p) for p in a.est]
    labels = a.label or [os.path.basename(p) for p in a.est]

    try:
        log = C.read_log(a.log)
    except (OSError, EOFError, ValueError, IndexError) as e:
        raise UsageError("cannot read log '%s': %s" % (a.log, e))
    n = len(log.scans)
    if n < 2:
        raise UsageError("log '%s' has %d scan(s) with a pose; need at least 2" % (a.log, n))
    if a.failed_pair is not None and not (0 <= a.failed_pair < n - 1):
        raise UsageError("--failed-pair %d out of range (0 .. %d)" % (a.failed_pair, n - 2))
    title = a.title or os.path.basename(a.log)

    for path, est in zip(a.est, ests):
        other = sum(1 for (i, j) in est if j != i + 1)
        outside = sum(1 for (i, j) in est if j == i + 1 and not (0 <= i < n - 1))
        if other or outside:
            print("note: %s: %d non-consecutive pair(s) ignored, %d pair(s) outside the log's %d scans"
                  % (path, other, outside, n), file=sys.stderr)

    import numpy as np
    results = [evaluate(C, log, est) for est in ests]
    for label, (te, re_, failed) in zip(labels, results):
        present = ~np.isnan(te)
        nf = int(failed.sum())
        med_t = float(np.median(te[present])) if present.any() else float("nan")
        med_r = float(np.median(re_[present])) if present.any() else float("nan")
        print("%s: pairs %d (present %d, missing %d), failures %d, fail %.2f %%, "
              "median trans err %.4f m, median rot err %.3f deg"
              % (label, n - 1, int(present.sum()), n - 1 - int(present.sum()), nf,
                 100.0 * nf / (n - 1), med_t, med_r))

    pair = a.failed_pair
    if pair is None:
        te, _, failed = results[0]
        cand = np.where(failed & ~np.isnan(te))[0]
        if len(cand):
            pair = int(cand[np.argmax(te[cand])])

    outputs = []
    out = a.out_prefix + "-trajectory.png"
    plot_trajectory(plt, C, log, ests, labels, pair, title, out, a.dpi)
    outputs.append(out)
    out = a.out_prefix + "-errors.png"
    plot_errors(plt, results, labels, pair, title, out, a.dpi)
    outputs.append(out)
    if pair is not None:
        out = "%s-pair-%d.png" % (a.out_prefix, pair)
        plot_pair(plt, C, log, ests[0], labels[0], results[0], pair, title, out, a.dpi)
        outputs.append(out)
    else:
        print("note: %s has no failed pair with an estimate; no pair plot" % labels[0], file=sys.stderr)
    for out in outputs:
        print("wrote %s" % out)
    return 0


if __name__ == "__main__":
    try:
        sys.exit(main())
    except UsageError as e:
        print("plot_relpose.py: error: %s" % e, file=sys.stderr)
        sys.exit(2)
    except OSError as e:  # e.g. an output file that cannot be written
        print("plot_relpose.py: error: %s" % e, file=sys.stderr)
        sys.exit(2)
