#!/usr/bin/env bash
# probebench impulse at 16^2: the table's row is probefit eval's mean L1 on the same stratified texels
# (core's impulse L1 over whole kernels against probefit's model measured from the lobe), one FIS row
# per bias follows, and tables of another size or a bad sample count are refused (exit 2).
set -euo pipefail
: "${PROBEBENCH:?}" "${PROBEFIT:?}" "${TABLES:?}"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
fail() { echo "FAIL: $*" >&2; exit 1; }

"$PROBEBENCH" impulse "$TABLES/gltf16_quad8.json" --samples 32 --fis-bias 0 0.5 --texels 96 >"$work/out.md" 2>"$work/err" ||
    fail "impulse: $(cat "$work/err")"
"$PROBEFIT" eval "$TABLES/gltf16_quad8.json" --texels stratified --budget 96 >"$work/eval.txt" || fail "probefit eval"
python3 - "$work/out.md" "$work/eval.txt" <<'PY' || fail "$(cat "$work/out.md")"
import sys
rows = {cells[0]: cells[1:] for cells in ([c.strip() for c in line.strip().strip("|").split("|")]
        for line in open(sys.argv[1]) if line.startswith("| ") and not line.startswith("| method"))}
assert list(rows) == ["gltf16_quad8", "fis32-bias0", "fis32-bias0.5"], list(rows)
evals = [float(line.split()[3]) for line in open(sys.argv[2]) if line.startswith("level") and " mean " in line]
table = [float(v) for v in rows["gltf16_quad8"]]
assert len(table) == len(evals) == 3, (table, evals)
for a, b in zip(table, evals):
    assert abs(a - b) <= 1e-4, (table, evals)
for name in ["fis32-bias0", "fis32-bias0.5"]:
    assert all(0.0 < float(v) < 2.0 for v in rows[name]), rows[name]
PY

refused() { # expected text, args...
    local text=$1 rc=0
    shift
    "$PROBEBENCH" impulse "$@" >/dev/null 2>"$work/err" || rc=$?
    [[ $rc == 2 ]] || fail "exit $rc for: $*"
    grep -qF -- "$text" "$work/err" || fail "message for $*: $(cat "$work/err")"
}
refused "differ from" "$TABLES/gltf16_quad8.json" "$TABLES/gltf32_quad8.json"
refused "--samples 0" "$TABLES/gltf16_quad8.json" --samples 0
echo "cli_impulse: ok"
