#!/usr/bin/env bash
# probefit from the command line: a small fit reaches the L1 it records, more --init taps and more
# --starts and --hops are never worse, --estimate and tail report, and bad input gets exit code 2, a one-line
# error naming the option or file, and no output files.
set -u
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
failures=0
fail() { echo "FAIL $*"; failures=$((failures + 1)); }

# A small fit; eval must reproduce what it recorded, over the stratified set and over all texels.
"$PROBEFIT" fit --size 16 --levels 4 --taps 4 --form quad --out "$work/small" >"$work/fit.log" || fail "small fit: exit $?"
for f in small.json small.h small.glsl; do [[ -s $work/$f ]] || fail "small fit: $f missing"; done
"$PROBEFIT" eval "$work/small.json" --texels stratified --check 1e-3 >"$work/eval.log" ||
    fail "eval stratified differs: $(cat "$work/eval.log")"
"$PROBEFIT" eval "$work/small.json" --texels all --check 1e-3 >"$work/eval.log" || fail "eval all differs: $(cat "$work/eval.log")"
# eval --cells prints the fit's L1 over cells beside the exact one, within a few percent of it.
"$PROBEFIT" eval "$work/small.json" --texels stratified --cells >"$work/cells.log" || fail "eval --cells: exit $?"
[[ $(grep -c 'over cells 0\.[0-9]* ([-+][0-9.]*%)' "$work/cells.log") -eq 3 ]] || fail "eval --cells: $(cat "$work/cells.log")"
awk -F'[()%]' '/over cells/ { d = $(NF - 2); if (d < -5 || d > 5) bad = 1 } END { exit bad }' "$work/cells.log" ||
    fail "eval --cells: the cells' L1 is not within 5% of the exact one: $(cat "$work/cells.log")"
# eval --budget N measures N stratified texels per level, which the table has no record of (its own
# budget it has): at 4x the texels the mean moves by a few percent at most.
"$PROBEFIT" eval "$work/small.json" --texels stratified --budget 2048 >"$work/budget.log" || fail "eval --budget: exit $?"
[[ $(grep -c 'budget 2048 per level' "$work/budget.log") -eq 1 && $(grep -c 'not recorded' "$work/budget.log") -eq 3 ]] ||
    fail "eval --budget: $(cat "$work/budget.log")"
"$PROBEFIT" eval "$work/small.json" --texels stratified >"$work/own.log"
awk 'FILENAME == ARGV[1] { if (/^level [1-3] mean/) own[$2] = $4; next }
     /^level [1-3] mean/ { r = $4 / own[$2]; if (r < 0.95 || r > 1.05) { print "level " $2 ": " $4 " against " own[$2]; bad = 1 } }
     END { exit bad }' "$work/own.log" "$work/budget.log" || fail "eval --budget: the mean moved by more than 5%"
# The fitted levels are far better than the lobe-shaped start (0.29 to 0.6 at this size).
awk '/^level [1-3] mean/ { if ($4 > 0.2) bad = 1 } END { exit bad }' "$work/eval.log" ||
    fail "small fit L1 above 0.2: $(cat "$work/eval.log")"

# export --fis-level hands a level to FIS (the JSON, the header and the GLSL record the count), and
# LEVEL:0 hands it back, leaving the table as it was.
"$PROBEFIT" export "$work/small.json" --fis-level 2:24 --out "$work/handoff" >"$work/handoff.log" || fail "export --fis-level: exit $?"
grep -q '"fisSamples": 24' "$work/handoff.json" && grep -q 'kFisSamples\[4\] = {0, 0, 24, 0};' "$work/handoff.h" &&
    grep -q 'probeTableFisSamples\[4\] = int\[\](0, 0, 24, 0);' "$work/handoff.glsl" || fail "export --fis-level: not recorded"
"$PROBEFIT" export "$work/handoff.json" --fis-level 2:0 --out "$work/back" >/dev/null || fail "export --fis-level 2:0: exit $?"
cmp -s "$work/back.json" "$work/small.json" || fail "export --fis-level 2:0 does not give the table back"

# The Charlie lobe (sheen): the table records its lobe, eval reproduces its records against the Charlie
# reference, and every level is fitted (level 0 too, which a GGX table copies): levels 1-3 end below
# half their start (about 0.4 of it); level 0, whose ring is narrower than a texel, below its start.
"$PROBEFIT" fit --size 16 --levels 4 --taps 4 --form quad --lobe charlie --iterations 10 --coarse-iterations 20 --out "$work/sheen" \
    >"$work/sheen.log" || fail "charlie fit: exit $?"
grep -q '"lobe": "charlie"' "$work/sheen.json" && grep -q 'kLobe = "charlie"' "$work/sheen.h" || fail "charlie fit: no lobe recorded"
"$PROBEFIT" eval "$work/sheen.json" --texels all --check 1e-3 >"$work/sheen-eval.log" ||
    fail "charlie eval differs: $(cat "$work/sheen-eval.log")"
[[ $(grep -c '^level [0-3] mean' "$work/sheen-eval.log") -eq 4 ]] || fail "charlie eval: not every level: $(cat "$work/sheen-eval.log")"
awk '/start lobe layout: L1/ { start[$2] = $7 }
     / done: L1/ { if ($5 >= ($2 == 0 ? 1 : 0.5) * start[$2]) { print "level " $2; bad = 1 } } END { exit bad }' "$work/sheen.log" ||
    fail "charlie fit: a level ends too near its start: $(grep -E 'start lobe|done' "$work/sheen.log")"
"$PROBEFIT" fit --size 16 --levels 4 --taps 4 --form quad --lobe charlie --init "$work/small.json" --out "$work/out" \
    2>"$work/stderr" >/dev/null
[[ $? -eq 2 ]] && grep -q 'fitted for the ggx lobe, not charlie' "$work/stderr" ||
    fail "a GGX --init for a Charlie fit: $(cat "$work/stderr")"

# The same inputs give the same table, whatever the number of threads.
OMP_NUM_THREADS=1 "$PROBEFIT" fit --size 16 --levels 4 --taps 4 --form quad --out "$work/single" >/dev/null || fail "single-thread fit"
cmp -s <(grep -v fitSeconds "$work/small.json") <(grep -v fitSeconds "$work/single.json") ||
    fail "the fit with 1 thread differs from the fit with the default threads"

"$PROBEFIT" fit --size 16 --levels 4 --taps 4 --form quad --jobs 1 --out "$work/jobs1" >/dev/null || fail "--jobs 1 fit"
cmp -s <(grep -v fitSeconds "$work/small.json") <(grep -v fitSeconds "$work/jobs1.json") ||
    fail "the fit with --jobs 1 differs from the fit with every core"

# --no-eval: the fit alone, its table without an exact L1; probefit eval --record measures it afterwards
# and gives the table of the fit that measured its stratified texels itself (--no-full-eval).
"$PROBEFIT" fit --size 16 --levels 4 --taps 4 --form quad --iterations 10 --no-eval --out "$work/alone" >"$work/alone.log" ||
    fail "--no-eval fit: exit $?"
[[ $(grep -c '^level [1-3] done: L1 over cells 0\.' "$work/alone.log") -eq 3 ]] || fail "--no-eval: $(grep done "$work/alone.log")"
python3 -c 'import json, sys
levels = [l for l in json.load(open(sys.argv[1]))["levels"] if l["alpha"] > 0]
sys.exit(any(l["stratified"]["mean"] >= 0 or l["all"]["mean"] >= 0 or l["minWeightSum"] <= 0 for l in levels))' "$work/alone.json" ||
    fail "--no-eval: a level records an L1, or no weight sum"
"$PROBEFIT" eval "$work/alone.json" --texels stratified --record "$work/judged" >/dev/null || fail "eval --record: exit $?"
"$PROBEFIT" fit --size 16 --levels 4 --taps 4 --form quad --iterations 10 --no-full-eval --out "$work/measured" >/dev/null ||
    fail "--no-full-eval fit: exit $?"
cmp -s <(grep -v fitSeconds "$work/judged.json") <(grep -v fitSeconds "$work/measured.json") ||
    fail "--no-eval, then eval --record, differs from --no-full-eval"
# Its levels are finished without records: --resume from it fits nothing.
cp "$work/alone.json" "$work/again.resume.json"
"$PROBEFIT" fit --size 16 --levels 4 --taps 4 --form quad --iterations 10 --no-eval --resume --out "$work/again" >"$work/again.log" ||
    fail "--no-eval --resume: exit $?"
[[ $(grep -c '^level [1-3] resumed: L1 not measured' "$work/again.log") -eq 3 ]] ||
    fail "--no-eval --resume refitted: $(grep -E 'resumed|done' "$work/again.log")"
cmp -s <(grep -v fitSeconds "$work/alone.json") <(grep -v fitSeconds "$work/again.json") || fail "--no-eval --resume changed the table"
"$PROBEFIT" fit --size 16 --levels 4 --taps 4 --form quad --no-eval --no-full-eval --out "$work/both" 2>"$work/stderr" >/dev/null
[[ $? -eq 2 ]] && grep -q -- '--no-eval' "$work/stderr" || fail "--no-eval with --no-full-eval: $(cat "$work/stderr")"
"$PROBEFIT" eval "$work/alone.json" --texels stratified --budget 100 --record "$work/budget" 2>"$work/stderr" >/dev/null
[[ $? -eq 2 && ! -e $work/budget.json ]] && grep -q -- '--record' "$work/stderr" || fail "eval --record --budget: $(cat "$work/stderr")"
mkdir "$work/folder.json"
timeout 60 "$PROBEFIT" eval "$work/alone.json" --texels stratified --record "$work/folder" 2>"$work/stderr" >/dev/null
[[ $? -eq 2 && -d $work/folder.json && ! -e $work/folder.h ]] && grep -q -- '--record .*folder' "$work/stderr" ||
    fail "eval --record onto a folder: $(cat "$work/stderr")"

# An interrupted fit writes no table and leaves its checkpoint; --resume takes the finished levels from
# it and ends at the table of an uninterrupted fit.
"$PROBEFIT" fit --size 16 --levels 4 --taps 4 --form quad --iterations 200 --out "$work/cut" >"$work/cut.log" 2>&1 &
fit_pid=$!
# Levels run at once: the first to finish is the one the checkpoint must hold. The checkpoint is
# written (renamed into place) after the level's last line, so wait for it before the signal.
for _ in $(seq 600); do
    [[ -s $work/cut.resume.json ]] && break
    sleep 0.05
done
first=$(awk '/^level [0-9]+ all texels/ { print $2; exit }' "$work/cut.log")
kill -INT $fit_pid
wait $fit_pid
code=$?
[[ $code -eq 130 ]] || fail "SIGINT: exit $code, expected 130 (the signal)"
compgen -G "$work/cut.json" >/dev/null || compgen -G "$work/cut.h" >/dev/null || compgen -G "$work/.cut*" >/dev/null &&
    fail "SIGINT left a table or a staging file: $(ls -a "$work")"
[[ -s $work/cut.resume.json ]] || fail "SIGINT: no checkpoint after level $first"
"$PROBEFIT" fit --size 16 --levels 4 --taps 4 --form quad --iterations 200 --resume --out "$work/cut" >"$work/resumed.log" ||
    fail "--resume: exit $?"
grep -q "^level $first resumed" "$work/resumed.log" || fail "--resume did not take level $first: $(head -5 "$work/resumed.log")"
[[ ! -e $work/cut.resume.json ]] || fail "--resume: the finished fit left its checkpoint"
"$PROBEFIT" fit --size 16 --levels 4 --taps 4 --form quad --iterations 200 --out "$work/whole" >/dev/null || fail "uninterrupted fit"
cmp -s <(grep -v fitSeconds "$work/cut.json") <(grep -v fitSeconds "$work/whole.json") ||
    fail "the resumed fit differs from the uninterrupted one"
"$PROBEFIT" fit --size 16 --levels 4 --taps 4 --form quad --iterations 100 --out "$work/other-cut" >/dev/null || fail "fit to copy"
cp "$work/cut.json" "$work/other-cut.resume.json"
"$PROBEFIT" fit --size 16 --levels 4 --taps 4 --form quad --iterations 100 --resume --out "$work/other-cut" 2>"$work/stderr" >/dev/null
[[ $? -eq 2 ]] && grep -q -- '--resume' "$work/stderr" || fail "--resume from another fit's checkpoint: $(cat "$work/stderr")"

# More taps are never worse: 8 taps from the 4-tap table (--init) reach at most its L1 at every level.
"$PROBEFIT" fit --size 16 --levels 4 --taps 8 --form quad --init "$work/small.json" --iterations 10 --no-full-eval \
    --out "$work/eight" >/dev/null || fail "8-tap fit from --init"
"$PROBEFIT" eval "$work/small.json" --texels stratified >"$work/eval4.log"
"$PROBEFIT" eval "$work/eight.json" --texels stratified >"$work/eval8.log"
paste -d' ' <(grep '^level [1-3] mean' "$work/eval4.log") <(grep '^level [1-3] mean' "$work/eval8.log") >"$work/pairs.log"
[[ $(wc -l <"$work/pairs.log") -eq 3 ]] || fail "--init comparison: missing levels"
awk '{ n = NF / 2; if ($(n + 4) > $4 + 1e-12) { print "level " $2 ": 8 taps " $(n + 4) " > 4 taps " $4; bad = 1 } } END { exit bad }' \
    "$work/pairs.log" || fail "8 taps worse than the 4-tap --init table: $(cat "$work/pairs.log")"

# --estimate says how long the fit takes and writes nothing.
"$PROBEFIT" fit --size 16 --levels 4 --taps 4 --form quad --estimate >"$work/estimate.log" || fail "--estimate: exit $?"
grep -q '^estimate: about [0-9]* s' "$work/estimate.log" || fail "--estimate: no estimate line: $(cat "$work/estimate.log")"
# --starts 2 --screen-all fits each level from the best start and from an importance layout, and
# keeps the lower objective (here the L1: no seam term, no --init; measured exactly, as the records
# are, so that the objective and the record are one number).
"$PROBEFIT" fit --size 16 --levels 4 --taps 4 --form quad --iterations 10 --no-full-eval --starts 2 --screen-all --measure exact \
    --bank none --out "$work/two" \
    >"$work/two.log" || fail "two starts"
[[ $(grep -c '^level [1-3] objective after the fit from' "$work/two.log") -eq 6 ]] || fail "--starts 2: not two fits per level"
awk '/objective after the fit from/ { f = $NF == "s" ? $(NF - 2) : $NF; if (!($2 in best) || f < best[$2]) best[$2] = f }
     / done: L1 / { if ($5 > best[$2] + 1e-9) { print "level " $2 ": kept " $5 ", best " best[$2]; bad = 1 } } END { exit bad }' \
    "$work/two.log" || fail "--starts 2 did not keep the best fit: $(grep -E 'objective|done' "$work/two.log")"
# Without --screen-all every start runs Levenberg-Marquardt on the coarse texels, and only the lowest
# goes on to the whole solver. The bank's best levels are starts too (--bank-starts): here two tables
# of 4 taps, each with a level near level 1's alpha (1/9), so level 1 has three starts: the best of
# the candidates (the lobe layout, the bank's best), the bank's second and an importance layout.
# Level 2 (96 texels, no coarse ones) runs each of its starts through the whole solver.
mkdir -p "$work/bank"
tables=$(dirname "$0")/../tables
cp "$tables/gltf128_quad4.json" "$tables/authors128_quad4.json" "$work/bank/"
"$PROBEFIT" fit --size 16 --levels 4 --taps 4 --form quad --iterations 10 --no-full-eval --starts 2 --measure exact \
    --bank "$work/bank" --bank-starts 2 --out "$work/screened" >"$work/screened.log" || fail "screened starts"
[[ $(grep -c '^level 1 objective after Levenberg-Marquardt from' "$work/screened.log") -eq 3 &&
    $(grep -c '^level 1 objective after Levenberg-Marquardt from bank' "$work/screened.log") -eq 1 &&
    $(grep -c '^level 1 objective after the fit' "$work/screened.log") -eq 0 ]] ||
    fail "not three screened starts at level 1, one from the bank: $(grep objective "$work/screened.log")"
[[ $(grep -c '^level 2 objective after the fit from' "$work/screened.log") -eq 3 &&
    $(grep -c '^level 2 objective after Levenberg-Marquardt' "$work/screened.log") -eq 0 ]] ||
    fail "level 2 (no coarse texels) did not fit each start in full: $(grep '^level 2 objective' "$work/screened.log")"
# The start that goes on is the one with the lowest objective after Levenberg-Marquardt.
python3 - "$work/screened.log" <<'PY' || fail "the start that went on was not the lowest: $(grep objective "$work/screened.log")"
import re, sys
best, kept = {}, {}
for line in open(sys.argv[1]):
    m = re.match(r"level (\d+) objective after Levenberg-Marquardt from (.*): f ([0-9.]+)", line)
    if m and (m[1] not in best or float(m[3]) < best[m[1]][1]):
        best[m[1]] = (m[2], float(m[3]))
    m = re.match(r"level (\d+) objective lowest after Levenberg-Marquardt: (.*) goes on: f ([0-9.]+)", line)
    if m:
        kept[m[1]] = (m[2], float(m[3]))
sys.exit(0 if best and kept == best else f"{best} {kept}")
PY
# --hops 2 refits a level twice from the fit moved at random, and keeps a hop only where it lowers the
# objective: the level ends at or below the same fit without hops (one level, so both start alike).
for hops in 0 2; do
    "$PROBEFIT" fit --size 16 --levels 4 --taps 4 --form quad --iterations 10 --init "$work/small.json" --fit-levels 2 --hops $hops \
        --measure exact --out "$work/hops$hops" >"$work/hops$hops.log" || fail "--hops $hops"
done
[[ $(grep -c '^level 2 objective after hop [12]:' "$work/hops2.log") -eq 2 ]] || fail "--hops 2: not two hops"
grep -q '; then 2 hops' "$work/hops2.json" || fail "--hops: not in the table's solver text"
awk '/^level 2 done: L1/ { l1[FILENAME] = $5 }
     END { if (!(a in l1) || !(b in l1) || l1[b] > l1[a] + 1e-12) { print l1[a], l1[b]; exit 1 } }' \
    a="$work/hops0.log" b="$work/hops2.log" "$work/hops0.log" "$work/hops2.log" ||
    fail "--hops 2 ended above the fit without hops: $(grep -h '^level 2 done' "$work/hops0.log" "$work/hops2.log")"
"$PROBEFIT" fit --size 16 --levels 4 --taps 4 --form quad --hops -1 --out "$work/neg" >"$work/neg.log" 2>&1
[[ $? -eq 2 && $(wc -l <"$work/neg.log") -eq 1 && ! -e $work/neg.json ]] || fail "--hops -1: not one line and exit 2"
# --fit-levels refits only the levels named: the others keep the first --init's coefficients bit for bit.
# The fit takes the tail and checker terms too, and reports the checker term before and after.
"$PROBEFIT" fit --size 16 --levels 4 --taps 4 --form quad --iterations 10 --init "$work/small.json" --fit-levels 2 --tail-weight 2 \
    --checker-weight 4 --out "$work/level2" >"$work/level2.log" || fail "--fit-levels 2"
[[ $(grep -c '^level 2 checker term \(at the start\|after the fit\): mean c [0-9.]' "$work/level2.log") -eq 2 ]] ||
    fail "--checker-weight: no checker term reported: $(grep -E 'checker|done' "$work/level2.log")"
[[ $(grep -c '^level [13] copied from --init' "$work/level2.log") -eq 2 && $(grep -c '^level 2 done' "$work/level2.log") -eq 1 ]] ||
    fail "--fit-levels 2: not level 2 alone fitted: $(grep -E 'copied|done' "$work/level2.log")"
python3 - "$work/small.json" "$work/level2.json" <<'PY' || fail "--fit-levels 2 did not keep levels 0, 1 and 3"
import json, sys
a, b = (json.load(open(f))["levels"] for f in sys.argv[1:])
sys.exit(0 if all(a[m]["coefficients"] == b[m]["coefficients"] for m in (0, 1, 3)) else "a level other than 2 changed")
PY
# Its solver text names the level it fitted and carries the init's for the levels it copied.
python3 - "$work/small.json" "$work/level2.json" <<'PY' || fail "--fit-levels 2: solver text without its provenance"
import json, sys
init, refit = (json.load(open(f))["solver"] for f in sys.argv[1:])
sys.exit(0 if refit.startswith("levels 2: ") and refit.endswith(f"the other levels copied from the first --init: [{init}]") else refit)
PY
# --fresh refits a level without the init's filter: from the lobe layout and the level before, none
# kept aside. At a strong seam weight a plain refit keeps the init's filter, whose L1 is lower, and so
# its seam term; the fresh refit keeps its own fit and a weaker seam term.
for mode in plain fresh; do
    "$PROBEFIT" fit --size 16 --levels 4 --taps 4 --form quad --iterations 10 --init "$work/small.json" --fit-levels 2 --seam-weight 8 \
        $([[ $mode == fresh ]] && echo --fresh) --out "$work/$mode" >"$work/$mode.log" || fail "--fit-levels 2 ($mode)"
done
grep -q '^level 2 kept the exact --init' "$work/plain.log" || fail "plain refit at seam weight 8 did not keep the --init's filter"
grep -q '^level 2 \(start --init\|kept the exact --init\)' "$work/fresh.log" && fail "--fresh: the --init took part in level 2"
awk '/^level 2 seam term after the fit/ { s[FILENAME] = $(NF - 2) }
     END { if (!(a in s) || !(b in s) || s[b] >= s[a]) { print s[a], s[b]; exit 1 } }' \
    a="$work/plain.log" b="$work/fresh.log" "$work/plain.log" "$work/fresh.log" ||
    fail "--fresh: seam term not below the plain refit's: $(grep -h '^level 2 seam term after' "$work/plain.log" "$work/fresh.log")"
python3 - "$work/small.json" "$work/fresh.json" <<'PY' || fail "--fresh did not keep levels 0, 1 and 3"
import json, sys
a, b = (json.load(open(f))["levels"] for f in sys.argv[1:])
sys.exit(0 if all(a[m]["coefficients"] == b[m]["coefficients"] for m in (0, 1, 3)) else "a level other than 2 changed")
PY
# tail prints every level with alpha > 0 at the three texels, and exits 0 or 1 (in or out of the bound).
"$PROBEFIT" tail "$work/small.json" >"$work/tail.log"
code=$?
[[ $code -le 1 ]] || fail "tail: exit $code"
[[ $(grep -c '^level [1-3] radius .*face centre.*edge.*corner' "$work/tail.log") -eq 3 ]] || fail "tail: $(cat "$work/tail.log")"

head -c 300 "$work/small.json" >"$work/truncated.json"
# A complete table file of the wrong layout: it says 8 taps, its coefficients are for 4.
sed 's/"taps": 4,/"taps": 8,/' "$work/small.json" >"$work/wrong-layout.json"
grep -q '"taps": 8,' "$work/wrong-layout.json" || fail "could not make the wrong-layout table"
"$PROBEFIT" fit --size 32 --levels 4 --taps 4 --form const --iterations 1 --no-full-eval --out "$work/other" >/dev/null || fail "other fit"

expect_refused() { # name, expected text in the message, args...
    local name=$1 text=$2
    shift 2
    "$PROBEFIT" "$@" 2>"$work/stderr" >/dev/null
    local code=$?
    [[ $code -eq 2 ]] || fail "$name: exit code $code, expected 2"
    [[ $(wc -l <"$work/stderr") -eq 1 ]] || fail "$name: not one line on stderr: $(cat "$work/stderr")"
    grep -qF -- "$text" "$work/stderr" || fail "$name: message lacks '$text': $(cat "$work/stderr")"
    compgen -G "$work/out*" >/dev/null && fail "$name: output written"
    rm -f "$work"/out*
    echo "ok $name: $(cat "$work/stderr")"
}
fit() { echo fit --taps 4 --form quad --out "$work/out" "$@"; }
expect_refused size-not-pow2   "--size"                 $(fit --size 12)
expect_refused size-one        "--size"                 $(fit --size 1)
expect_refused too-many-levels "--levels"               $(fit --size 16 --levels 6)
expect_refused negative-levels "--levels"               $(fit --size 16 --levels -1)
expect_refused zero-levels     "--levels"               $(fit --size 16 --levels 0)
expect_refused weighting-renamed "--weighting is now --pyramid-weighting" \
    fit --taps 4 --form quad --out "$work/out" --size 16 --weighting solid-angle
expect_refused empty-levels    "--levels: empty value" fit --taps 4 --form quad --out "$work/out" --size 16 --levels ''
expect_refused many-iterations "--iterations"           $(fit --size 16 --iterations 1000000000)
expect_refused many-starts     "--starts"               $(fit --size 16 --starts 100000)
expect_refused lobe            "--lobe"                 $(fit --size 16 --lobe phong)
expect_refused many-hops       "--hops"                 $(fit --size 16 --hops 100000)
expect_refused measure         "--measure"              $(fit --size 16 --measure fast)
expect_refused jobs            "--jobs"                 $(fit --size 16 --jobs -3)
expect_refused bank            "--bank"                 $(fit --size 16 --bank "$work/no/such/folder")
expect_refused taps            "--taps"                 fit --size 16 --taps 6 --form quad --out "$work/out"
expect_refused form            "--form"                 fit --size 16 --taps 4 --form cubic --out "$work/out"
expect_refused mapping         "--mapping"              $(fit --size 16 --mapping bogus)
expect_refused pyramid         "--pyramid"              $(fit --size 16 --pyramid gauss)
expect_refused solver          "--solver"               $(fit --size 16 --solver newton)
expect_refused iterations      "--iterations"           $(fit --size 16 --iterations 0)
expect_refused missing-out     "--out"                  fit --size 16 --taps 4 --form quad
expect_refused unwritable-out  "--out"                  fit --size 16 --taps 4 --form quad --out "$work/no/such/dir/out"
expect_refused truncated-init  "$work/truncated.json"   $(fit --size 16 --levels 4 --init "$work/truncated.json")
expect_refused missing-init    "$work/nope.json"        $(fit --size 16 --levels 4 --init "$work/nope.json")
expect_refused init-other-size "--init $work/other.json" $(fit --size 16 --levels 4 --init "$work/other.json")
expect_refused eval-truncated  "$work/truncated.json"   eval "$work/truncated.json"
expect_refused tail-truncated  "$work/truncated.json"   tail "$work/truncated.json"
expect_refused starts          "--starts"               $(fit --size 16 --starts 0)
expect_refused eval-layout     "$work/wrong-layout.json" eval "$work/wrong-layout.json"
expect_refused init-layout     "$work/wrong-layout.json" $(fit --size 16 --levels 4 --init "$work/wrong-layout.json")
expect_refused seam-weight     "--seam-weight"          $(fit --size 16 --seam-weight -1)
expect_refused seam-pairs      "--seam-pairs"           $(fit --size 16 --seam-pairs 0)
expect_refused tail-weight     "--tail-weight"          $(fit --size 16 --tail-weight nan)
expect_refused checker-weight  "--checker-weight"       $(fit --size 16 --checker-weight -2)
expect_refused fit-levels-init "--fit-levels"           $(fit --size 16 --levels 4 --fit-levels 1)
expect_refused fit-levels-range "--fit-levels"          $(fit --size 16 --levels 4 --init "$work/small.json" --fit-levels 4)
expect_refused fit-levels-empty "--fit-levels: empty value" \
    fit --taps 4 --form quad --out "$work/out" --size 16 --levels 4 --init "$work/small.json" --fit-levels ''
expect_refused fit-levels-gap  "--fit-levels"           $(fit --size 16 --levels 4 --init "$work/small.json" --fit-levels 1,,2)
expect_refused fresh           "--fresh"                $(fit --size 16 --levels 4 --init "$work/small.json" --fresh)
expect_refused eval-texels     "--texels"               eval "$work/small.json" --texels some
expect_refused fis-level-range "--fis-level 4:24"       export "$work/small.json" --fis-level 4:24 --out "$work/out"
expect_refused fis-level-form  "--fis-level 1-24"       export "$work/small.json" --fis-level 1-24 --out "$work/out"
expect_refused fis-level-many  "65536"                  export "$work/small.json" --fis-level 1:70000 --out "$work/out"
expect_refused fis-level-copy  "level 0 is a copy"      export "$work/small.json" --fis-level 0:24 --out "$work/out"
expect_refused eval-cells-all  "--cells"                eval "$work/small.json" --texels all --cells
expect_refused eval-budget-all "--budget"               eval "$work/small.json" --texels all --budget 1024
expect_refused eval-budget-0   "--budget"               eval "$work/small.json" --texels stratified --budget 0
expect_refused select-shape    "other: not the shape of small" select "$work/small.json" "$work/other.json" --out "$work/out"
expect_refused select-missing  "$work/nope.json"        select "$work/small.json" "$work/nope.json" --out "$work/out"
expect_refused select-unwritable "--out"                select "$work/small.json" --out "$work/no/such/dir/out"
expect_refused mix-count       "1 source tables for 4 output levels" mix "$work/small.json" --out "$work/out"
expect_refused mix-unwritable  "--out" \
    mix "$work/small.json" "$work/small.json" "$work/small.json" "$work/small.json" --out "$work/no/such/dir/out"

# A folder where PREFIX.h goes is refused before the fit, and nothing is written beside it.
mkdir -p "$work/dir-out/t.h"
"$PROBEFIT" fit --size 16 --levels 4 --taps 4 --form quad --out "$work/dir-out/t" >/dev/null 2>"$work/stderr"
[[ $? -eq 2 && $(wc -l <"$work/stderr") -eq 1 ]] && grep -q 't.h: exists and is not a regular file' "$work/stderr" ||
    fail "a folder at PREFIX.h: $(cat "$work/stderr")"
[[ $(find "$work/dir-out" -mindepth 1 | wc -l) -eq 1 ]] || fail "a folder at PREFIX.h: wrote $(ls -a "$work/dir-out")"

# select from one table keeps it: the same coefficients and errors at every level.
"$PROBEFIT" select "$work/small.json" --out "$work/kept" >"$work/select.log" || fail "select one table: exit $?"
cmp -s <(grep -v '"solver"' "$work/small.json") <(grep -v '"solver"' "$work/kept.json") ||
    fail "select from one table changed it: \
$(diff <(grep -v '"solver"' "$work/small.json") <(grep -v '"solver"' "$work/kept.json") | head -5)"

[[ $failures -eq 0 ]] || { echo "$failures failures"; exit 1; }
