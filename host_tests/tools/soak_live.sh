#!/bin/sh
# soak_live.sh BUILD_DIR OUT_DIR [MINUTES] - the live soak of issue 18,
# item 3: `lmsego sim` on a pseudo-terminal and `lmsego run` on its other
# end, whole 180 deg / 1 deg scans at 500000 baud (75 Hz), for MINUTES of
# wall time (default 30), sampling the run process's memory and CPU.
#
#   cmake --preset release && cmake --build --preset release
#   nice -n 10 host_tests/tools/soak_live.sh build/release /tmp/soak 30
#
# Not run by CI (it takes MINUTES). run is given --scans N, N = MINUTES *
# 60 * 75, so it stops by itself after N scans; the simulator is stopped
# right after. Every ~10 s the script samples VmRSS (/proc/PID/status, kB)
# and utime+stime (/proc/PID/stat, clock ticks) of the run process into
# OUT_DIR/samples.txt (elapsed_s rss_kb cpu_ticks). At the end it writes
# OUT_DIR/summary.txt: RSS first / last / max, CPU seconds per minute over
# the first and the last 5 minutes, the lines expected (N - 1: the first
# scan has no motion and no line; the others are numbered 1 .. N - 1), the lines
# received, the scan numbers missing from the CSV, the gaps between
# consecutive time_s longer than 1.5 scan intervals (a scan lost on the
# line or in a restart), the largest latency_ms and the lines later than
# 100 ms, the restarts (lines flagged FIRST), both programs' counter lines
# (stderr), and the scans the simulator sent that never got a line.
# Exit status 0 when no line is lost (lines = N - 1, no missing number, no
# gap, at most 2 scans sent but not received: in flight at the stop, queue
# dropped=0), 1 otherwise. SOAK_LIVE_SUMMARY_ONLY=1 only writes the summary
# of the run already in OUT_DIR. SOAK_LIVE_MOVING=1 runs `run --moving`:
# each line is followed by its scan's moving objects ("o," lines, counted
# apart in the summary), the loop's objects detector in the live path too.
set -eu

if [ $# -lt 2 ] || [ $# -gt 3 ]; then
    echo "usage: $0 BUILD_DIR OUT_DIR [MINUTES]" >&2
    exit 2
fi
build=$1
out=$2
minutes=${3:-30}
lmsego=$build/bin/lmsego
if [ ! -x "$lmsego" ]; then
    echo "soak_live.sh: $lmsego missing: build the release preset first" >&2
    exit 1
fi
mkdir -p "$out"
link=$out/scanner.pty
scans=$((minutes * 60 * 75))
ticks=$(getconf CLK_TCK)
run_status=0
if [ "${SOAK_LIVE_SUMMARY_ONLY:-0}" = 1 ]; then
    # Only the summary of the run already in OUT_DIR (its MINUTES given).
    run_status=$(sed -n 's/^run exit status //p' "$out/summary.txt" 2>/dev/null || echo 0)
    run_status=${run_status:-0}
else
    "$lmsego" sim --baud 9600 --link "$link" >"$out/sim.out" 2>"$out/sim.err" &
    sim_pid=$!
    i=0
    while [ ! -e "$link" ] && [ $i -lt 50 ]; do
        sleep 0.1
        i=$((i + 1))
    done
    moving=
    if [ "${SOAK_LIVE_MOVING:-0}" = 1 ]; then
        moving=--moving
    fi
    # $moving unquoted: empty or one word.
    # shellcheck disable=SC2086
    "$lmsego" run --port "$link" --variant 180,1 --scans "$scans" $moving >"$out/run.csv" 2>"$out/run.err" &
    run_pid=$!

    # elapsed_s rss_kb cpu_ticks: fields 14 and 15 of /proc/PID/stat (after
    # the command name in parentheses, which holds no space here).
    sample() {
        if [ -r "/proc/$run_pid/status" ]; then
            rss=$(awk '/^VmRSS:/ {print $2}' "/proc/$run_pid/status" 2>/dev/null || true)
            cpu=$(awk '{print $14 + $15}' "/proc/$run_pid/stat" 2>/dev/null || true)
            if [ -n "$rss" ] && [ -n "$cpu" ]; then
                echo "$1 $rss $cpu" >>"$out/samples.txt"
            fi
        fi
    }

    : >"$out/samples.txt"
    start=$(date +%s)
    sample 0
    limit=$((minutes * 60 + 120))
    while kill -0 "$run_pid" 2>/dev/null; do
        sleep 10
        now=$(($(date +%s) - start))
        sample "$now"
        if [ "$now" -gt "$limit" ]; then
            echo "soak_live.sh: run still going after ${limit} s: stopping it" >&2
            kill -INT "$run_pid" 2>/dev/null || true
        fi
    done
    wait "$run_pid" || run_status=$?
    kill -INT "$sim_pid" 2>/dev/null || true
    wait "$sim_pid" || true
fi

# The summary. Scan numbers start at 1; time_s is column 2.
awk -F, -v n="$((scans - 1))" -v ticks="$ticks" -v status="$run_status" \
    -v samples="$out/samples.txt" -v runerr="$out/run.err" -v simerr="$out/sim.err" '
    NR == 1 { next }
    $1 == "o" { objects++; next }
    {
        lines++
        if ($1 != prev + 1) missing += $1 - prev - 1
        prev = $1
        if (NR > 2) {
            d = $2 - t
            if (d > 1.5 / 75) gaps++
        }
        t = $2
        if ($18 + 0 > lmax) lmax = $18 + 0
        if ($18 + 0 > 100) late++
        if ($9 % 2 == 1) restarts++
    }
    END {
        while ((getline l < samples) > 0) {
            split(l, f, " ")
            k++; s[k] = f[1]; r[k] = f[2]; c[k] = f[3]
            if (f[2] > rmax) rmax = f[2]
        }
        # CPU per minute over the first and the last 300 s of samples.
        for (j = 1; j <= k && s[j] - s[1] < 300; j++) a = j
        for (j = k; j >= 1 && s[k] - s[j] < 300; j--) b = j
        first = (s[a] > s[1]) ? (c[a] - c[1]) / ticks * 60 / (s[a] - s[1]) : 0
        last = (s[k] > s[b]) ? (c[k] - c[b]) / ticks * 60 / (s[k] - s[b]) : 0
        printf "samples %d over %d s\n", k, s[k]
        printf "rss_kb first %d last %d max %d\n", r[1], r[k], rmax
        printf "cpu_s_per_min first_5min %.3f last_5min %.3f\n", first, last
        printf "cpu_s_total %.2f\n", c[k] / ticks
        printf "lines expected %d received %d missing_numbers %d time_gaps %d\n", n, lines, missing + (n - prev), gaps + 0
        printf "latency_ms max %.1f lines_over_100ms %d\n", lmax, late + 0
        printf "restarts (lines flagged FIRST) %d\n", restarts + 0
        printf "object lines (o,) %d\n", objects + 0
        printf "run exit status %d\n", status
        while ((getline l < runerr) > 0) if (l ~ /scans=|dropped=/) print "run: " l
        while ((getline l < simerr) > 0) {
            if (l ~ /scans_sent=/) {
                print "sim: " l
                split(l, p, "scans_sent=")
                sent = p[2] + 0
            }
        }
        # Sent by the simulator, never a line: lost on the line or in a
        # restart (a few more leave after run stops: in flight).
        printf "scans sent by sim %d, run stopped after %d: not received %d\n", sent, n + 1, sent - (n + 1)
        lost = (lines != n) || (missing + (n - prev) != 0) || (gaps + 0 != 0) || (status != 0) ||
            (sent - (n + 1) > 2)
        printf "%s\n", lost ? "LOST LINES" : "no line lost"
        exit lost
    }' "$out/run.csv" >"$out/summary.txt" && ok=0 || ok=1
cat "$out/summary.txt"
if grep -q "dropped=[1-9]" "$out/run.err"; then
    echo "soak_live.sh: the run queue dropped scans" >&2
    ok=1
fi
exit "$ok"
