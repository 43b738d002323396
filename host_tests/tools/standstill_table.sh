#!/usr/bin/env bash
# standstill_table.sh [BIN_DIR [OUT_DIR]]: standing still in stopgo's queue
# (issue 17; docs/experiments.md, "Standing still"): the whole stopgo
# scenario at 181 and 361 values, without noise and with 1 and 3 cm of
# range noise (seed 5), replayed as cast within the default budget; failed
# pairs (pairs_error.py), how many of them are flagged and silent
# (nees.py), and what the lines say while the vehicle stands
# (standstill.py: drift, mean, largest speed). BIN_DIR holds lmsworld and
# lmsego (default build/release/bin). About 20 s on two cores.
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
bin=${1:-build/release/bin}
out=${2:-$(mktemp -d)}
mkdir -p "${out}"

printf '| values | noise | failed pairs | flagged | silent | standing lines | drift, m | mean, mm | largest speed, m/s (its flags) | lines over 3 mm |\n'
printf '| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |\n'
for res in 1 0.5; do
    for noise in 0 1 3; do
        name=stopgo_${res}_${noise}
        "${bin}/lmsworld" --scenario stopgo --res "${res}" --noise-cm "${noise}" --seed 5 \
            -o "${out}/${name}.lms" --truth "${out}/${name}.pairs" >/dev/null
        "${bin}/lmsego" replay --sweep instant "${out}/${name}.lms" >"${out}/${name}.csv" 2>/dev/null
        read -r pairs failed <<<"$(python3 "${here}/pairs_error.py" "${out}/${name}.pairs" \
            "${out}/${name}.csv" | awk '/^pairs/ {print $2, $4}')"
        read -r flagged silent <<<"$(python3 "${here}/nees.py" "${out}/${name}.pairs" \
            "${out}/${name}.csv" | tail -n 1 | sed 's/.*flagged \([0-9]*\),.*silent \([0-9]*\) of.*/\1 \2/')"
        read -r lines drift mean speed flags over <<<"$(python3 "${here}/standstill.py" \
            "${out}/${name}.pairs" "${out}/${name}.csv" |
            sed 's/standing lines \([0-9]*\)  drift \([0-9.]*\) m  mean \([0-9.]*\) mm  max speed \([0-9.]*\) m\/s (flags \([0-9]*\))  over 3 mm \([0-9]*\)/\1 \2 \3 \4 \5 \6/')"
        values=$([[ ${res} == 1 ]] && echo 181 || echo 361)
        printf '| %s | %s cm | %s of %s | %s | %s | %s | %s | %s | %s (%s) | %s |\n' "${values}" "${noise}" \
            "${failed}" "${pairs}" "${flagged}" "${silent}" "${lines}" "${drift}" "${mean}" "${speed}" \
            "${flags}" "${over}"
    done
done
