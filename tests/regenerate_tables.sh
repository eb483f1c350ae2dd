#!/usr/bin/env bash
# scripts/regenerate-tables on the committed gltf16_quad8 with a short recipe: the jobs run as Slurm
# array tasks (each run here with SLURM_ARRAY_TASK_ID set) and through GNU parallel give the same table,
# bit for bit; no regenerated level is worse than the committed one (the refit keeps it); the report
# names every level; a finished job is not run again; with no names every table but the mixes is
# planned; bad names and job numbers are refused (exit 2).
set -uo pipefail
: "${PROBEFIT:?}"
export PROBEFIT
root=$(cd "$(dirname "$0")/.." && pwd)
regenerate=$root/scripts/regenerate-tables
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
fail() { echo "FAIL: $*" >&2; exit 1; }
recipe="--iterations 4 --hops 1"

"$regenerate" plan --out "$work/slurm" --recipe "$recipe" gltf16_quad8 >"$work/plan.log" || fail "plan: $(cat "$work/plan.log")"
grep -q '^3 jobs' "$work/plan.log" || fail "plan: expected 3 jobs (levels 1 to 3): $(cat "$work/plan.log")"
for k in 1 2 3; do
    SLURM_ARRAY_TASK_ID=$k "$regenerate" task "$work/slurm" >>"$work/tasks.log" || fail "array task $k: $(cat "$work/tasks.log")"
done
before=$(stat -c %Y "$work/slurm/levels/gltf16_quad8.1.json")
sleep 1
SLURM_ARRAY_TASK_ID=1 "$regenerate" task "$work/slurm" || fail "array task 1 again"
[[ $(stat -c %Y "$work/slurm/levels/gltf16_quad8.1.json") == "$before" ]] || fail "a finished job ran again"
"$regenerate" assemble "$work/slurm" >/dev/null || fail "assemble"

command -v parallel >/dev/null || fail "GNU parallel is not installed (scripts/setup installs it)"
"$regenerate" --out "$work/parallel" --recipe "$recipe" gltf16_quad8 >"$work/parallel.log" 2>&1 ||
    fail "through GNU parallel: $(tail -5 "$work/parallel.log")"
for f in "$work"/slurm/tables/gltf16_quad8.{json,h,glsl} "$work"/parallel/tables/gltf16_quad8.{json,h,glsl}; do
    [[ -s $f ]] || fail "$f missing"
done
python3 - "$root/tables/gltf16_quad8.json" "$work/slurm/tables/gltf16_quad8.json" "$work/parallel/tables/gltf16_quad8.json" <<'PY' ||
import json, sys
committed, slurm, parallel = (json.load(open(p)) for p in sys.argv[1:])
assert [l["coefficients"] for l in slurm["levels"]] == [l["coefficients"] for l in parallel["levels"]], "the runners differ"
for m, (new, old) in enumerate(zip(slurm["levels"], committed["levels"])):
    for key in ["stratified", "all"]:
        assert new[key]["mean"] <= old[key]["mean"] * (1 + 1e-9), (m, key, new[key]["mean"], old[key]["mean"])
assert slurm["solver"].startswith("scripts/regenerate-tables:") and committed["solver"] in slurm["solver"]
PY
    fail "the regenerated tables"
"$PROBEFIT" eval "$work/parallel/tables/gltf16_quad8.json" --texels stratified --check 1e-3 >/dev/null ||
    fail "eval does not reproduce the regenerated table's records"
grep -q '^| gltf16_quad8 | [0-9]* | [0-9]* | 1: 0\.[0-9]* ([0-9.]*x), 2: .*, 3: ' "$work/parallel/report.md" ||
    fail "report: $(cat "$work/parallel/report.md")"
grep -q 'GNU parallel, wall time' "$work/parallel/report.md" || fail "report: no runner and wall time"

refused() { # expected text, args...
    local text=$1
    shift
    "$regenerate" "$@" >/dev/null 2>"$work/err"
    local code=$?
    [[ $code -eq 2 ]] || fail "exit $code for: $*"
    grep -qF -- "$text" "$work/err" || fail "message for $*: $(cat "$work/err")"
}
# With no names: every committed table but the mixes, which the assembly remakes from their sources.
"$regenerate" plan --out "$work/all" >/dev/null || fail "plan of every table"
planned=$(cut -d' ' -f1 "$work/all/jobs.txt" | sort -u | wc -l)
unmixed=$(find "$root/tables" -maxdepth 1 -name '*.json' ! -name '*mix*' | wc -l)
[[ $planned -eq $unmixed ]] || fail "plan of every table: $planned tables, expected $unmixed"

refused "no committed table" plan --out "$work/bad" nosuch64_quad8
refused "mixed table" plan --out "$work/bad" gltf128_quadmix8
refused "no job number" task "$work/slurm"
refused "has 3 jobs" task "$work/slurm" 4
refused "--threads" plan --out "$work/bad" --threads 0 gltf16_quad8
echo "regenerate_tables: ok"
