#!/usr/bin/env bash
# real_trust.sh BUILD_DIR OUT_DIR [SHARED_DIR]: the real logs' lines of
# docs/estimator.md, "Trust" (issue 16): intel and aces at stride 1 and
# their own spacing (2.92 s, 3.00 s), within the default budget; their
# failed pairs (0.10 m, and 2 deg then 1 deg) that carry no trust flag and
# whose covariance, with the reference's own 2 cm and 0.3 deg, does not
# hold the error (nees.py), and of those the ones whose scans the reference
# fits better (pair_fit.py: the others are more likely the reference's
# errors). pair_fit needs Debian's python3-numpy under /usr/bin/python3.
set -euo pipefail
if [ $# -lt 2 ] || [ $# -gt 3 ]; then
    echo "usage: $0 BUILD_DIR OUT_DIR [SHARED_DIR]" >&2
    exit 2
fi
lmsego=$1/bin/lmsego
out=$2
here=$(cd "$(dirname "$0")" && pwd)
shared=${3:-$here/../../../shared}
mkdir -p "${out}"
for log in intel aces; do
    period=2.92
    [ "${log}" = aces ] && period=3.00
    data=${shared}/data/${log}-corrected.log.gz
    "${lmsego}" import-carmen "${data}" -o "${out}/${log}.lms" >/dev/null
    python3 "${shared}/tools/relpose_eval.py" "${data}" --write-baseline reference --stride 1 \
        >"${out}/${log}.ref"
    "${lmsego}" replay --period "${period}" --pairs "${out}/${log}.pairs" "${out}/${log}.lms" \
        >"${out}/${log}.csv" 2>/dev/null
    /usr/bin/python3 "${here}/pair_fit.py" "${data}" "${out}/${log}.pairs" 2>/dev/null |
        awk '!/^#/ {print $2, ($12 > $10) ? "reference" : "estimate"}' >"${out}/${log}.fit"
    for deg in 2 1; do
        python3 "${here}/nees.py" "${out}/${log}.ref" "${out}/${log}.csv" --ref-sigma 0.02,0.3 \
            --fail-deg "${deg}" --list >"${out}/${log}.silent${deg}"
        ours=0
        for scan in $(sed -n 's/^  silent [0-9]*-\([0-9]*\):.*/\1/p' "${out}/${log}.silent${deg}"); do
            [ "$(awk -v s="${scan}" '$1 == s {print $2}' "${out}/${log}.fit")" = reference ] &&
                ours=$((ours + 1))
        done
        echo "${log} at ${deg} deg: $(grep '^failures' "${out}/${log}.silent${deg}");" \
            "where the reference fits better: ${ours}"
    done
done
