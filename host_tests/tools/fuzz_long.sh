#!/usr/bin/env bash
# fuzz_long.sh - a long libFuzzer run in chunks that can be stopped and
# resumed: each chunk is one process of RUNS inputs from the shared working
# corpus; its executions, edges and time go to TALLY only when it finishes
# (a chunk cut short counts nothing). WORKERS chunks run side by side on
# the same corpus (libFuzzer reloads what the others found). It stops when
# the finished chunks add up to TOTAL executions, or at the first finding
# (the crash input is in DIR/artifacts/).
#
#   fuzz_long.sh FUZZER DIR TOTAL [RUNS] [WORKERS] [MAX_LEN] [SEEDS]
#
# FUZZER: the target binary; DIR: the working directory (corpus/, tally,
# logs, artifacts/); TOTAL: executions to reach; RUNS: inputs a chunk
# (default 100000); WORKERS: default 1; MAX_LEN: default 4096; SEEDS: a
# seed corpus copied into DIR/corpus when it is empty. Runs at nice 19.
# docs/robustness.md: how the long runs were made.
set -u
fuzzer=$(realpath "$1")
dir=$2
total=$3
runs=${4:-100000}
workers=${5:-1}
max_len=${6:-4096}
seeds=${7:-}
mkdir -p "$dir/corpus" "$dir/artifacts" "$dir/logs"
if [ -n "$seeds" ] && [ -z "$(ls -A "$dir/corpus")" ]; then
    cp "$seeds"/* "$dir/corpus/"
fi
tally=$dir/tally
touch "$tally"

done_runs() {
    awk '{s += $2} END {print s + 0}' "$tally"
}

chunk() {
    local worker=$1 n=$2
    local seed=$(( (n * 16 + worker) % 2147483647 + 1 ))
    local log=$dir/logs/chunk-$n-$worker.log
    local start=$(date +%s)
    nice -n 19 "$fuzzer" "$dir/corpus" -runs="$runs" -max_len="$max_len" -seed="$seed" \
        -print_final_stats=1 -artifact_prefix="$dir/artifacts/" >"$log" 2>&1
    local rc=$?
    local secs=$(( $(date +%s) - start ))
    if [ $rc -ne 0 ]; then
        echo "worker $worker chunk $n: exit $rc, see $log" >&2
        touch "$dir/stop"
        return
    fi
    local execs cov
    execs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log")
    cov=$(grep -o 'cov: [0-9]*' "$log" | tail -1 | cut -d' ' -f2)
    # chunk, executions, seconds, edges, seed
    echo "$n-$worker ${execs:-0} $secs ${cov:-0} $seed" >>"$tally"
}

n=$(wc -l <"$tally")
rm -f "$dir/stop"
while [ "$(done_runs)" -lt "$total" ] && [ ! -e "$dir/stop" ]; do
    for w in $(seq 1 "$workers"); do
        chunk "$w" "$n" &
    done
    wait
    n=$((n + 1))
done
echo "executions: $(done_runs) in $(wc -l <"$tally") chunks; tally: $tally"
[ ! -e "$dir/stop" ]
