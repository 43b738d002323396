#!/usr/bin/env bash
# busy_table.sh [BIN_DIR [OUT_DIR]]: the busy streets of issue 17
# (docs/experiments.md, "Busy streets"): each lmsworld scenario at 181 and
# 361 values, replayed as cast within the default budget; failed pairs
# (0.10 m or 1 deg) and the median translation error (pairs_error.py),
# and how many of the failures carry a trust flag or are silent
# (nees.py); then the same with an odometry prior whose translations are
# 5 % long (scaled_prior.py). BIN_DIR holds lmsworld and lmsego (default
# build/release/bin). About a minute on two cores.
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
bin=${1:-build/release/bin}
out=${2:-$(mktemp -d)}
mkdir -p "${out}"

printf '| scenario | values | failed pairs | median translation error, mm | flagged | silent | with a prior 5 %% long: failed | median, mm | silent |\n'
printf '| --- | --- | --- | --- | --- | --- | --- | --- | --- |\n'
for scenario in traffic platoon overtake crossing pedestrians stopgo; do
    for res in 1 0.5; do
        name=${scenario}_${res}
        "${bin}/lmsworld" --scenario "${scenario}" --res "${res}" -o "${out}/${name}.lms" \
            --truth "${out}/${name}.pairs" >/dev/null
        "${bin}/lmsego" replay --sweep instant "${out}/${name}.lms" >"${out}/${name}.csv" 2>/dev/null
        read -r pairs failed median <<<"$(python3 "${here}/pairs_error.py" "${out}/${name}.pairs" \
            "${out}/${name}.csv" | awk '/^pairs/ {p = $2; f = $4} /^translation m/ {m = $8}
                                        END {printf "%s %s %.1f", p, f, 1000 * m}')"
        read -r flagged silent <<<"$(python3 "${here}/nees.py" "${out}/${name}.pairs" \
            "${out}/${name}.csv" | tail -n 1 | sed 's/.*flagged \([0-9]*\),.*silent \([0-9]*\) of.*/\1 \2/')"
        python3 "${here}/scaled_prior.py" "${out}/${name}.pairs" 1.05 "${out}/${name}.prior"
        "${bin}/lmsego" replay --sweep instant --prior "${out}/${name}.prior" "${out}/${name}.lms" \
            >"${out}/${name}_prior.csv" 2>/dev/null
        read -r p_failed p_median <<<"$(python3 "${here}/pairs_error.py" "${out}/${name}.pairs" \
            "${out}/${name}_prior.csv" | awk '/^pairs/ {f = $4} /^translation m/ {m = $8}
                                              END {printf "%s %.1f", f, 1000 * m}')"
        p_silent=$(python3 "${here}/nees.py" "${out}/${name}.pairs" "${out}/${name}_prior.csv" |
            tail -n 1 | sed 's/.*silent \([0-9]*\) of.*/\1/')
        values=$([[ ${res} == 1 ]] && echo 181 || echo 361)
        printf '| %s | %s | %s of %s | %s | %s | %s | %s | %s | %s |\n' "${scenario}" "${values}" \
            "${failed}" "${pairs}" "${median}" "${flagged}" "${silent}" "${p_failed}" "${p_median}" \
            "${p_silent}"
    done
done
