#!/usr/bin/env bash
# probebench sweep's sampling settings: with hardware sampling and --pyramid-format rgba16f the report
# and sweep.md's device line name both, and --summarize keeps them; a pyramid format with exact
# sampling is refused before the references run (exit 2, reason on stderr, nothing written).
set -euo pipefail
: "${PROBEBENCH:?}" "${TABLES:?}"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
cd "$work"

fail() { echo "FAIL: $*" >&2; exit 1; }
sweep=(sweep --size 16 --synthetic sunsky --samples 8 --fis-bias 0 --pyramid bspline --fis-maps cube --repeat 1 --tables "$TABLES")

"$PROBEBENCH" "${sweep[@]}" --sampling hardware --pyramid-format rgba16f --out half >/dev/null 2>&1 || fail "hardware, rgba16f pyramid"
python3 -c "import json,sys; r=json.load(open('half/report.json'))
sys.exit(r['sampling'] != 'hardware' or r['pyramid_format'] != 'rgba16f')" || fail "report: sampling or pyramid format"
grep -q "hardware sampling, rgba16f pyramid" half/sweep.md || fail "sweep.md: device line $(head -1 half/sweep.md)"
"$PROBEBENCH" sweep --summarize half --out again >/dev/null 2>&1 || fail "--summarize"
grep -q "hardware sampling, rgba16f pyramid" again/sweep.md || fail "--summarize: device line $(head -1 again/sweep.md)"

rc=0
"$PROBEBENCH" "${sweep[@]}" --sampling exact --pyramid-format rgba16f --out refused >/dev/null 2>err.txt || rc=$?
grep -q "^reference" err.txt && fail "the refusal came after the references ran"
[[ $rc == 2 ]] || fail "a pyramid format with exact sampling exited $rc, expected 2"
grep -q -- "--pyramid-format rgba16f" err.txt || fail "stderr lacks the option: $(cat err.txt)"
[[ ! -e refused ]] || fail "a refused sweep wrote output"
echo "cli_sweep_sampling: ok"
