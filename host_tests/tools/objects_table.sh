#!/usr/bin/env bash
# objects_table.sh [BIN_DIR [OUT_DIR]]: the moving objects of issue 17,
# item 3 (docs/experiments.md, "Moving objects (issue 17, item 3)"): each
# full-length lmsworld busy-street scenario at 181 and 361 values,
# replayed as cast (--sweep instant) with `lmsego replay --objects`, and
# scored by objects_score.py from 0.27 s on (scan 20 at 75 Hz, 10 at
# 37.5 Hz: the detector needs a reference 0.2 s back and three
# sightings). The platoon is replayed with the truth pairs as its prior:
# without one the estimator misbehaves there (docs/experiments.md, "Busy
# streets"), and the ego-motion's error would be all this measures.
# BIN_DIR holds lmsworld and lmsego (default build/release/bin).
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
bin=${1:-build/release/bin}
out=${2:-$(mktemp -d)}
mkdir -p "${out}"

printf '| scenario | values | scans | moving vehicle targets | detected | pedestrian targets | detected | false per scan | velocity error median, m/s | mean | p90 |\n'
printf '| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |\n'
for scenario in traffic platoon overtake crossing pedestrians stopgo; do
    for res in 1 0.5; do
        name=${scenario}_${res}
        "${bin}/lmsworld" --scenario "${scenario}" --res "${res}" -o "${out}/${name}.lms" \
            --truth "${out}/${name}.pairs" --objects "${out}/${name}.objects" >/dev/null
        prior=()
        if [[ ${scenario} == platoon ]]; then
            prior=(--prior "${out}/${name}.pairs")
        fi
        "${bin}/lmsego" replay --sweep instant "${prior[@]}" --objects "${out}/${name}.csv" \
            "${out}/${name}.lms" >/dev/null 2>&1
        first=$([[ ${res} == 1 ]] && echo 20 || echo 10)
        python3 "${here}/objects_score.py" "${out}/${name}.objects" "${out}/${name}.csv" \
            --from "${first}" >"${out}/${name}.score"
        values=$([[ ${res} == 1 ]] && echo 181 || echo 361)
        awk -v s="${scenario}${prior[*]:+ (prior)}" -v v="${values}" '
            /^scans/ {n = $2}
            /^vehicles:/ {vt = $2; vd = $4}
            /^pedestrians:/ {pt = $2; pd = $4}
            /^false/ {f = $3; gsub(/[()]/, "", f)}
            /^velocity error/ {md = $0; sub(/.*median /, "", md); sub(/ .*/, "", md)
                               mn = $0; sub(/.*mean /, "", mn); sub(/ .*/, "", mn)
                               p9 = $0; sub(/.*p90 /, "", p9)}
            END {
                vcell = (vt > 0) ? sprintf("%d (%.1f %%)", vd, 100 * vd / vt) : "-"
                pcell = (pt > 0) ? sprintf("%d (%.1f %%)", pd, 100 * pd / pt) : "-"
                printf "| %s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s |\n", s, v, n, vt,
                       vcell, pt, pcell, f, md == "" ? "-" : md, mn == "" ? "-" : mn,
                       p9 == "" ? "-" : p9
            }' "${out}/${name}.score"
    done
done
