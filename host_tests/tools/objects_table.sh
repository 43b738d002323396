#!/usr/bin/env bash
# objects_table.sh [BIN_DIR [OUT_DIR]]: the moving objects of issue 17,
# item 3 (docs/experiments.md, "Moving objects (issue 17, item 3)"): each
# full-length lmsworld busy-street scenario at 181 and 361 values,
# replayed as cast (--sweep instant) with `lmsego replay --objects`, and
# scored by objects_score.py from 0.27 s on (scan 20 at 75 Hz, 10 at
# 37.5 Hz: the detector needs a reference 0.2 s back and three
# sightings); then again with the truth pairs as the motion prior, which
# separates the detector's errors from the ego-motion's (the estimator
# misbehaves on the platoon without a prior, docs/experiments.md "Busy
# streets": its first columns measure that). About 70 s on two cores.
# BIN_DIR holds lmsworld and lmsego (default build/release/bin).
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
bin=${1:-build/release/bin}
out=${2:-$(mktemp -d)}
mkdir -p "${out}"

# One scoring as a table's cells: vehicle targets, detected, pedestrian
# targets, detected, false per scan, velocity error median / mean / p90.
cells() {
    awk '
        /^vehicles:/ {vt = $2; vd = $4}
        /^pedestrians:/ {pt = $2; pd = $4}
        /^false/ {f = $3; gsub(/[()]/, "", f)}
        /^velocity error.*median/ {md = $0; sub(/.*median /, "", md); sub(/ .*/, "", md)
                           mn = $0; sub(/.*mean /, "", mn); sub(/ .*/, "", mn)
                           p9 = $0; sub(/.*p90 /, "", p9)}
        END {
            vcell = (vt > 0) ? sprintf("%.1f %%", 100 * vd / vt) : "-"
            pcell = (pt > 0) ? sprintf("%.1f %%", 100 * pd / pt) : "-"
            printf "%s | %s | %s | %s | %s | %s | %s | %s", vt, vcell, pt, pcell, f,
                   md == "" ? "-" : md, mn == "" ? "-" : mn, p9 == "" ? "-" : p9
        }' "$1"
}

printf '| scenario | values | scans | vehicle targets | detected | pedestrian targets | detected | false per scan | velocity error median, m/s | mean | p90 | with the true motion as prior: vehicles detected | pedestrians detected | false per scan | velocity median | mean | p90 |\n'
printf '| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |\n'
for scenario in traffic platoon overtake crossing pedestrians stopgo; do
    for res in 1 0.5; do
        name=${scenario}_${res}
        "${bin}/lmsworld" --scenario "${scenario}" --res "${res}" -o "${out}/${name}.lms" \
            --truth "${out}/${name}.pairs" --objects "${out}/${name}.objects" >/dev/null
        first=$([[ ${res} == 1 ]] && echo 20 || echo 10)
        for run in est prior; do
            prior=()
            if [[ ${run} == prior ]]; then
                prior=(--prior "${out}/${name}.pairs")
            fi
            "${bin}/lmsego" replay --sweep instant "${prior[@]}" \
                --objects "${out}/${name}_${run}.csv" "${out}/${name}.lms" >/dev/null 2>&1
            python3 "${here}/objects_score.py" "${out}/${name}.objects" "${out}/${name}_${run}.csv" \
                --from "${first}" >"${out}/${name}_${run}.score"
        done
        values=$([[ ${res} == 1 ]] && echo 181 || echo 361)
        scans=$(awk '/^scans/ {print $2}' "${out}/${name}_est.score")
        est=$(cells "${out}/${name}_est.score")
        with=$(cells "${out}/${name}_prior.score" | awk -F' [|] ' '{printf "%s | %s | %s | %s | %s | %s", $2, $4, $5, $6, $7, $8}')
        printf '| %s | %s | %s | %s | %s |\n' "${scenario}" "${values}" "${scans}" "${est}" "${with}"
    done
done
