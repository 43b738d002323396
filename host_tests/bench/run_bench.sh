#!/bin/sh
# run_bench.sh BUILD_DIR - runs the codec benchmark of an existing build
# (it builds nothing) and counts instructions per byte with callgrind.
#
#   cmake -S . -B /tmp/h3rel -DCMAKE_BUILD_TYPE=Release -DLMSEGO_BUILD_TESTS=ON
#   cmake --build /tmp/h3rel --target bench_codec
#   host_tests/bench/run_bench.sh /tmp/h3rel
#
# Timing: bench_codec (median and best of 15 runs). Instructions: valgrind
# --tool=callgrind on `bench_codec --once`, collecting only inside
# bench_decode_pass (stream construction excluded); Ir / stream bytes.
set -eu

if [ $# -ne 1 ]; then
    echo "usage: $0 BUILD_DIR" >&2
    exit 2
fi
build=$1
# Programs land in <build>/bin (top-level CMAKE_RUNTIME_OUTPUT_DIRECTORY).
bench=$build/bin/bench_codec
if [ ! -x "$bench" ]; then
    bench=$build/host_tests/bench/bench_codec
fi
if [ ! -x "$bench" ]; then
    echo "run_bench.sh: no bench_codec in $build; build the bench_codec target first" >&2
    exit 1
fi

build_type=$(sed -n 's/^CMAKE_BUILD_TYPE:[A-Z]*=//p' "$build/CMakeCache.txt" 2>/dev/null || true)
if [ "$build_type" != "Release" ]; then
    echo "run_bench.sh: warning: $build is a '${build_type:-unknown}' build, not Release" >&2
fi
if grep -q '^LMSEGO_SANITIZE:BOOL=ON' "$build/CMakeCache.txt" 2>/dev/null; then
    echo "run_bench.sh: $build is built with sanitizers: no meaningful figures" >&2
    exit 1
fi

echo "machine: $(nproc) CPUs, $(sed -n 's/^model name[^:]*: //p' /proc/cpuinfo | head -n 1)"
echo "build:   $build ($build_type)"
echo
echo "== timing: $bench"
"$bench"

echo
echo "== callgrind: $bench --once (bench_decode_pass only)"
if ! command -v valgrind >/dev/null 2>&1; then
    echo "run_bench.sh: valgrind not found; skipping the instruction count" >&2
    exit 0
fi
out=$(mktemp "${TMPDIR:-/tmp}/bench_codec.callgrind.XXXXXX")
trap 'rm -f "$out"' EXIT
once=$(valgrind --tool=callgrind --toggle-collect=bench_decode_pass \
    --callgrind-out-file="$out" "$bench" --once 2>/dev/null)
echo "$once"
bytes=$(echo "$once" | sed -n 's/.*stream_bytes=\([0-9]*\).*/\1/p')
telegrams=$(echo "$once" | sed -n 's/.* telegrams=\([0-9]*\).*/\1/p')
# The totals line of a callgrind output file: "totals: <Ir>" (older
# versions write "summary:").
ir=$(sed -n 's/^totals: *\([0-9]*\).*/\1/p' "$out")
if [ -z "$ir" ]; then
    ir=$(sed -n 's/^summary: *\([0-9]*\).*/\1/p' "$out")
fi
if [ -z "$bytes" ] || [ -z "$telegrams" ] || [ -z "$ir" ]; then
    echo "run_bench.sh: could not read stream_bytes or the callgrind total" >&2
    exit 1
fi
awk -v ir="$ir" -v bytes="$bytes" -v telegrams="$telegrams" 'BEGIN {
    printf "Ir (bench_decode_pass): %d\n", ir
    printf "instructions per byte: %.2f\n", ir / bytes
    printf "instructions per telegram: %.0f\n", ir / telegrams
}'
