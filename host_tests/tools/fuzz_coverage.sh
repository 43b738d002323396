#!/usr/bin/env bash
# fuzz_coverage.sh NAME CORPUS OUT - the lines, regions and branches of the
# estimator that a fuzz target's corpus runs: NAME (fuzz_estimator,
# fuzz_moving or fuzz_itcp) built with clang's source-based coverage
# (-fprofile-instr-generate -fcoverage-mapping, no sanitizers), every input
# of CORPUS run once, then llvm-cov: OUT/report.txt (per file) and
# OUT/unrun.txt (the lines of estimator/*.c never run, with their file).
# Run from the repository root; docs/robustness.md quotes its figures.
set -eu
if [ $# -ne 3 ]; then
    echo "usage: $0 fuzz_estimator|fuzz_moving|fuzz_itcp CORPUS OUT" >&2
    exit 2
fi
name=$1
corpus=$2
out=$3
case $name in
fuzz_estimator | fuzz_moving | fuzz_itcp) ;;
*)
    echo "fuzz_coverage.sh: $name: fuzz_estimator, fuzz_moving or fuzz_itcp" >&2
    exit 2
    ;;
esac
mkdir -p "$out"
clang -std=c11 -O1 -g -fsanitize=fuzzer -fprofile-instr-generate -fcoverage-mapping \
    -Iestimator -Ihost_tests/fuzz "host_tests/fuzz/$name.c" estimator/*.c -o "$out/$name"
rm -f "$out"/*.profraw
LLVM_PROFILE_FILE="$out/run.profraw" "$out/$name" -runs=0 "$corpus" >"$out/run.log" 2>&1
llvm-profdata merge -o "$out/run.profdata" "$out/run.profraw"
llvm-cov report "$out/$name" -instr-profile="$out/run.profdata" estimator/*.c >"$out/report.txt"
: >"$out/unrun.txt"
for f in estimator/*.c; do
    llvm-cov show "$out/$name" -instr-profile="$out/run.profdata" "$f" |
        awk -v f="$f" -F'|' '$2 ~ /^ *0$/ {print f ":" ($1 + 0) ":" $3}' >>"$out/unrun.txt"
done
grep -E "INITED|DONE" "$out/run.log" | tail -1
cat "$out/report.txt"
