#!/usr/bin/env bash
# interlace_table.sh [BIN_DIR [OUT_DIR]]: the table of docs/estimator.md,
# "Interlaced scans and de-skewing" (issue 16): the highway of lmsworld
# (10-30 m/s, arcs at 0.5 rad/s) cast at once and with the mirror's timing,
# at 361 and 181 values, replayed as cast, not de-skewed and de-skewed,
# unbounded and within the default budget. Per row: failed pairs (0.10 m
# or 1 deg over every pair a line claims, nees.py) and the translation
# error's mean and median (mm) over the pairs after scan 60 (the cold start
# at 30 m/s), pairs_error.py. BIN_DIR holds lmsworld and lmsego (default
# build/release/bin). About a minute on two cores.
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
bin=${1:-build/release/bin}
out=${2:-$(mktemp -d)}
mkdir -p "${out}"

for res in 0.5 1; do
    "${bin}/lmsworld" --scenario highway --seed 1 --res "${res}" -o "${out}/at_once_${res}.lms" \
        --truth "${out}/at_once_${res}.pairs" >/dev/null
    "${bin}/lmsworld" --scenario highway --seed 1 --res "${res}" --timing lms \
        -o "${out}/mirror_${res}.lms" --truth "${out}/mirror_${res}.pairs" >/dev/null
done

# figures STREAM SWEEP BUDGET: "failed mean median"
figures() {
    local csv="${out}/$1.$2.$3.csv"
    "${bin}/lmsego" replay --sweep "$2" --budget "$3" "${out}/$1.lms" >"${csv}" 2>/dev/null
    local failed
    failed=$(python3 "${here}/nees.py" "${out}/$1.pairs" "${csv}" | tail -n 1 | sed 's/.*deg): \([0-9]*\),.*/\1/')
    awk -F, 'NR == 1 || $1 > 60' "${csv}" >"${csv}.after60"
    python3 "${here}/pairs_error.py" "${out}/$1.pairs" "${csv}.after60" |
        awk -v f="${failed}" '/^translation m/ {printf "%s %.2f %.2f", f, 1000 * $4, 1000 * $8}'
}

printf '| values | stream | replayed | failed unbounded (budget) | mm after scan 60, unbounded mean (median); budget mean |\n'
printf '| --- | --- | --- | --- | --- |\n'
for res in 0.5 1; do
    values=$([[ ${res} == 0.5 ]] && echo 361 || echo 181)
    for row in "at_once_${res} instant cast at once|as cast" \
        "mirror_${res} instant the mirror's timing|not de-skewed" \
        "mirror_${res} lms the mirror's timing|de-skewed"; do
        read -r stream sweep _ <<<"${row%%|*}"
        label=${row#* * }
        read -r f_none mean median <<<"$(figures "${stream}" "${sweep}" none)"
        read -r f_budget mean_budget _ <<<"$(figures "${stream}" "${sweep}" default)"
        printf '| %s | %s | %s | %s (%s) | %s (%s); %s |\n' "${values}" "${label%%|*}" "${label#*|}" \
            "${f_none}" "${f_budget}" "${mean}" "${median}" "${mean_budget}"
    done
done
