#!/bin/sh
# real_data.sh BUILD_DIR OUT_DIR [SHARED_DIR] - every real-data figure of
# docs/results.md, from the two CARMEN logs in SHARED_DIR/data (default:
# ../shared next to the repository).
#
#   cmake --preset release && cmake --build --preset release
#   host_tests/tools/real_data.sh build/release /tmp/real
#
# For intel and aces, stride 1 and stride 5, without and with the odometry
# prior: lmsego import-carmen, lmsego replay --budget none --pairs (the
# unbounded offline mode the main tables were made with; the default
# budget at the logs' own spacing has its own commands in
# docs/results.md), then the reference
# scorer relpose_eval.py (OUT_DIR/summary.txt). Stride 5 scores every pair
# (i, i+5), so it replays five streams, offsets 0..4, and joins their pairs.
# Then: time per scan (bench_estimator, no prior), which failed pairs the
# estimate fits better than the reference does (pair_fit.py), and the
# pictures (plot_relpose.py, OUT_DIR/img). The pictures and pair_fit need
# Debian's python3-matplotlib and python3-numpy under /usr/bin/python3;
# run as root, this script installs them with apt-get when they are missing.
# Takes about 10 minutes on two cores.
set -eu

if [ $# -lt 2 ] || [ $# -gt 3 ]; then
    echo "usage: $0 BUILD_DIR OUT_DIR [SHARED_DIR]" >&2
    exit 2
fi
build=$1
out=$2
here=$(cd "$(dirname "$0")" && pwd)
shared=${3:-$here/../../../shared}
lmsego=$build/bin/lmsego
bench=$build/bin/bench_estimator
eval_py=$shared/tools/relpose_eval.py
for f in "$lmsego" "$bench"; do
    if [ ! -x "$f" ]; then
        echo "real_data.sh: $f missing: build the release preset first" >&2
        exit 1
    fi
done
if [ ! -f "$eval_py" ] || [ ! -f "$shared/data/intel-corrected.log.gz" ]; then
    echo "real_data.sh: no logs or scorer under $shared (give SHARED_DIR)" >&2
    exit 1
fi
if ! /usr/bin/python3 -c 'import matplotlib, numpy' 2>/dev/null; then
    if [ "$(id -u)" = 0 ] && command -v apt-get >/dev/null; then
        apt-get install -y python3-matplotlib python3-numpy >/dev/null
    else
        echo "real_data.sh: needs python3-matplotlib and python3-numpy (apt-get install)" >&2
        exit 1
    fi
fi
mkdir -p "$out/img"

# run LOG STRIDE OFFSET: import, then replay without and with the prior.
run() {
    log=$1 stride=$2 offset=$3
    base=$out/$log.s$stride.o$offset
    "$lmsego" import-carmen "$shared/data/$log-corrected.log.gz" -o "$base.lms" \
        --odometry "$base.odom" --stride "$stride" --offset "$offset" 2>/dev/null
    steps="--scan-step $stride --scan-offset $offset"
    # shellcheck disable=SC2086
    "$lmsego" replay --budget none $steps --pairs "$base.est" "$base.lms" >/dev/null 2>&1
    # shellcheck disable=SC2086
    "$lmsego" replay --budget none $steps --prior "$base.odom" --pairs "$base.pest" "$base.lms" >/dev/null 2>&1
}

for log in intel aces; do
    # Two at a time (two cores).
    run $log 1 0 &
    run $log 5 0 &
    wait
    run $log 5 1 &
    run $log 5 2 &
    wait
    run $log 5 3 &
    run $log 5 4 &
    wait
    cp "$out/$log.s1.o0.est" "$out/$log-stride1-no-prior.pairs"
    cp "$out/$log.s1.o0.pest" "$out/$log-stride1-odometry.pairs"
    cat "$out/$log".s5.o?.est | sort -n -k1,1 > "$out/$log-stride5-no-prior.pairs"
    cat "$out/$log".s5.o?.pest | sort -n -k1,1 > "$out/$log-stride5-odometry.pairs"
done

{
    for log in intel aces; do
        for stride in 1 5; do
            python3 "$eval_py" "$shared/data/$log-corrected.log.gz" --stride $stride \
                --baseline odom "$out/$log-stride$stride-no-prior.pairs" \
                "$out/$log-stride$stride-odometry.pairs"
            echo
        done
    done
    for log in intel aces; do
        echo "== time per scan, $log, no prior (bench_estimator, $(nproc) CPUs)"
        "$bench" "$out/$log.s1.o0.lms"
        echo
    done
    for log in intel aces; do
        for kind in no-prior odometry; do
            echo "== $log stride 1 $kind: failed pairs the estimate fits better than the reference"
            /usr/bin/python3 "$here/pair_fit.py" "$shared/data/$log-corrected.log.gz" \
                "$out/$log-stride1-$kind.pairs" --failed-only --shared-tools "$shared/tools" |
                awk '/^#/ { print; next } { if ($12 < $10) lower++ }
                     END { print "# estimate score below the reference score in", lower + 0 }'
        done
        echo "== $log stride 1 no-prior: all pairs (is the median limited by the reference?)"
        /usr/bin/python3 "$here/pair_fit.py" "$shared/data/$log-corrected.log.gz" \
            "$out/$log-stride1-no-prior.pairs" --shared-tools "$shared/tools" | tail -n 1
    done
} > "$out/summary.txt"

for log in intel aces; do
    /usr/bin/python3 "$here/plot_relpose.py" "$shared/data/$log-corrected.log.gz" \
        "$out/$log-stride1-no-prior.pairs" "$out/$log-stride1-odometry.pairs" \
        --label "no prior" --label "odometry prior" --title "$log, stride 1" \
        --shared-tools "$shared/tools" --out-prefix "$out/img/$log" >/dev/null
done
cat "$out/summary.txt"
