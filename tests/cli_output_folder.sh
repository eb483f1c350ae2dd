#!/usr/bin/env bash
# Output folders under faults: `probefilter filter` runs killed (SIGKILL and SIGINT) at points
# spread over the whole run, the pause before the swap included, leave the output folder exactly as
# the previous run left it or whole as the new run writes it, never a mix; after SIGINT no staging
# folder is left, after SIGKILL the next run removes it. `probefilter synth`, which writes one file,
# interrupted (SIGINT, SIGTERM) while it writes a large probe leaves the previous file as it was and
# no staging file. Every command that writes a folder refuses `/`, the input's folder and a non-empty
# folder it did not write (exit 2, nothing changed; a FIFO or a huge report.json there is not its own).
# A write that fails keeps the previous output and leaves no parent folder the run created.
set -euo pipefail
: "${PROBEFILTER:?}" "${PROBEBENCH:?}"
# The bench's commands are probebench's, the rest probefilter's.
tool_for() { case $1 in compare | sweep) echo "$PROBEBENCH" ;; *) echo "$PROBEFILTER" ;; esac; }
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cd "$work"
"$PROBEFILTER" synth sky --size 16 --out sky.exr >/dev/null

python3 - "$PROBEFILTER" <<'PY'
import hashlib, json, os, shutil, signal, subprocess, sys, time

probefilter = sys.argv[1]
old_args = [probefilter, "filter", "sky.exr", "--method", "fis", "--samples", "16", "--size", "16", "--ktx2", "rgba16f"]
new_args = [probefilter, "filter", "sky.exr", "--method", "fis", "--samples", "8", "--size", "16", "--levels", "2"]
pause_ms = 300
env = dict(os.environ, PROBEFILTER_TEST_PAUSE_BEFORE_SWAP_MS=str(pause_ms))

def files(folder):
    found = {}
    for root, _, names in os.walk(folder):
        for name in names:
            path = os.path.join(root, name)
            found[os.path.relpath(path, folder)] = hashlib.sha256(open(path, "rb").read()).hexdigest()
    return found

def run(args, out, run_env=None):
    subprocess.run(args + ["--out", out], check=True, capture_output=True, env=run_env)

run(old_args, "old")
old = files("old")
run(new_args, "new")
new = files("new")
assert set(old) != set(new) and "level_3.exr" in old and "level_3.exr" not in new, (sorted(old), sorted(new))

def state(folder):
    if not os.path.isdir(folder):
        return "missing"
    now = files(folder)
    if now == old:
        return "old"
    # The new run's files are deterministic but for report.json's timings.
    same = set(now) == set(new) and all(now[n] == new[n] for n in new if n != "report.json")
    if same and json.load(open(os.path.join(folder, "report.json")))["level_count"] == 2:
        return "new"
    return "mixed"

def staging(pid=None):
    """Staging folders (.probefilter-<hash>-<pid>-<random>), of the run `pid` alone if given."""
    return [n for n in os.listdir(".") if n.startswith(".probefilter-") and (pid is None or n.split("-")[2] == str(pid))]

start = time.monotonic()
run(new_args, "timing", env)
duration = time.monotonic() - start

def staged_whole(pid):
    return any(os.path.exists(os.path.join(n, "report.json")) for n in staging(pid))

trials = 24  # per signal at points spread over the run, and 4 more in the pause with the new output staged whole
outcomes = {}
failures = 0
for k in range(trials + 4):
    delay = 1.2 * duration * (k + 0.5) / trials  # the last few finish before the signal
    for sig in (signal.SIGKILL, signal.SIGINT):
        shutil.rmtree("out", ignore_errors=True)
        shutil.copytree("old", "out")
        proc = subprocess.Popen(new_args + ["--out", "out"], env=env, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL,
                                preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL))
        if k < trials:
            time.sleep(delay)
        else:
            while proc.poll() is None and not staged_whole(proc.pid):
                time.sleep(0.005)
        proc.send_signal(sig)
        code = proc.wait()
        result = state("out")
        left = staging(proc.pid)  # a SIGKILLed run's may be there still
        outcomes[(sig.name, result)] = outcomes.get((sig.name, result), 0) + 1
        if k >= trials and result != "old":
            print(f"FAIL: {sig.name} in the pause before the swap (exit {code}): the output folder is {result}, not the old one")
            failures += 1
        elif result not in ("old", "new"):
            print(f"FAIL: {sig.name} at {delay:.3f} s (exit {code}): the output folder is {result}")
            failures += 1
        if sig == signal.SIGINT and left:
            print(f"FAIL: SIGINT at {delay:.3f} s (exit {code}) left {left}")
            failures += 1

# A killed run's staging folder is removed by the next run into the same folder.
run(new_args, "out")
if staging():
    print(f"FAIL: staging left after a complete run: {staging()}")
    failures += 1
print(f"{2 * (trials + 4)} killed runs over {duration:.2f} s each ({pause_ms} ms pause before the swap): "
      + ", ".join(f"{s} {r}: {n}" for (s, r), n in sorted(outcomes.items())))
sys.exit(1 if failures else 0)
PY

python3 - "$PROBEFILTER" <<'PY'
import os, signal, subprocess, sys, time

probefilter = sys.argv[1]
subprocess.run([probefilter, "synth", "sky", "--size", "16", "--out", "big.exr"], check=True, capture_output=True)
previous = open("big.exr", "rb").read()
failures = 0
for sig in (signal.SIGINT, signal.SIGTERM):
    proc = subprocess.Popen([probefilter, "synth", "sky", "--size", "1024", "--out", "big.exr"], stdout=subprocess.DEVNULL,
                            stderr=subprocess.DEVNULL, preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL))
    # The staging file appears when the writing starts (after the probe is made).
    while proc.poll() is None and not any(n.startswith(".big.exr.") and n.endswith(".partial") for n in os.listdir(".")):
        time.sleep(0.005)
    if proc.poll() is not None:
        print(f"FAIL: synth --size 1024 ended before {sig.name} could reach it while writing")
        failures += 1
        continue
    proc.send_signal(sig)
    code = proc.wait()
    left = sorted(n for n in os.listdir(".") if "big.exr" in n and n != "big.exr")
    if code != -sig or left or open("big.exr", "rb").read() != previous:
        print(f"FAIL: synth interrupted by {sig.name} while writing (exit {code}) left {left}, the previous file "
              + ("kept" if open("big.exr", "rb").read() == previous else "changed"))
        failures += 1
print(f"synth interrupted while writing: {failures} failure(s)")
sys.exit(1 if failures else 0)
PY

# Refusals: exit 2, one line naming the folder, nothing changed or created.
mkdir -p notes/sub && echo keep >notes/sub/todo.txt
failures=0
refused() { # expected text, arguments
    local text=$1
    shift
    local code=0
    "$(tool_for "$1")" "$@" >/dev/null 2>stderr || code=$?
    if [[ $code -ne 2 ]] || [[ $(wc -l <stderr) -ne 1 ]] || ! grep -qF -- "$text" stderr; then
        echo "FAIL: $* -> exit $code: $(cat stderr)"
        failures=$((failures + 1))
    fi
}
echo '{"probes": [{"name": "sky", "image": "sky.exr", "face_size": 16}], "materials": []}' >scene.json
refused "refusing to replace the root folder" filter sky.exr --size 16 --out /
refused "holds the input" filter sky.exr --size 16 --out .
refused "holds the input" run scene.json --out .
refused "holds the input" reference sky.exr --size 16 --out "$work"
commands=("filter sky.exr --size 16" "reference sky.exr --size 16" "run scene.json" "compare sky.exr --size 16" "sweep --size 16")
for command in "${commands[@]}"; do
    # shellcheck disable=SC2086
    refused "notes: is not empty and holds no report.json" $command --out notes
done
refused "--method nope" filter sky.exr --size 16 --method nope --out fresh/parents/out
[[ $(cat notes/sub/todo.txt) == keep && ! -e fresh ]] || { echo "FAIL: a refused run changed the disk"; failures=$((failures + 1)); }
if ! "$PROBEFILTER" filter sky.exr --size 16 --method fis --force --out notes >/dev/null 2>&1; then
    echo "FAIL: --force"
    failures=$((failures + 1))
fi
[[ -f notes/level_0.exr && ! -e notes/sub ]] || { echo "FAIL: --force did not replace the folder whole"; failures=$((failures + 1)); }

# A write that fails (a full disk; here the file-size limit, its signal ignored) fails the run, its
# last line says which file, and the previous output is kept whole; a run that fails removes the
# parent folders it created.
"$PROBEFILTER" reference sky.exr --size 16 --levels 2 --out kept >/dev/null 2>&1
before=$(cd kept && sha256sum ./*)
code=0
(trap '' XFSZ && ulimit -f 8 && "$PROBEFILTER" reference sky.exr --size 16 --levels 3 --out kept >/dev/null 2>stderr) || code=$?
if [[ $code -ne 2 ]] || ! tail -n 1 stderr | grep -qF ": cannot write (File too large)" ||
    [[ $(cd kept && sha256sum ./*) != "$before" ]] || compgen -G ".probefilter-*" >/dev/null; then
    echo "FAIL: a failed write -> exit $code: $(cat stderr); kept/ $(ls kept)"
    failures=$((failures + 1))
fi
code=0
(trap '' XFSZ && ulimit -f 8 && "$PROBEFILTER" reference sky.exr --size 16 --levels 3 --out made/new/out >/dev/null 2>stderr) ||
    code=$?
[[ $code -eq 2 && ! -e made ]] || { echo "FAIL: a failed run left its parent folders (exit $code)"; failures=$((failures + 1)); }
# What is in the way of the output is judged without reading it whole: a FIFO or a huge report.json
# is not probefilter's.
mkdir fifo huge && mkfifo fifo/report.json && head -c 20000000 /dev/zero | tr '\0' '[' >huge/report.json
refused "fifo: is not empty and holds no report.json" reference sky.exr --size 16 --out fifo
refused "huge: is not empty and holds no report.json" reference sky.exr --size 16 --out huge
# A staging folder is removed by a later run only when no process holds its flock: a live run's
# (here one this script locks) survives, a dead run's (unlocked) goes.
python3 - "$PROBEFILTER" <<'PY' || failures=$((failures + 1))
import fcntl, os, subprocess, sys
def fnv1a(name):
    h = 2166136261
    for c in name.encode():
        h = ((h ^ c) * 16777619) & 0xFFFFFFFF
    return f"{h:08x}"
live, dead = (f".probefilter-{fnv1a('shared')}-{pid}-0000000{k}" for k, pid in ((1, 1), (2, 2)))
for folder in (live, dead):
    os.mkdir(folder)
lock = os.open(live, os.O_RDONLY)
fcntl.flock(lock, fcntl.LOCK_EX)
subprocess.run([sys.argv[1], "filter", "sky.exr", "--size", "16", "--method", "fis", "--out", "shared"], check=True, capture_output=True)
if not os.path.isdir(live) or os.path.exists(dead):
    sys.exit(f"FAIL: after a run into shared/, the locked staging folder {'is' if os.path.isdir(live) else 'is not'} there "
             f"and the unlocked one {'is' if os.path.exists(dead) else 'is not'}")
PY
echo "cli_output_folder: refusals: $failures failure(s)"
[[ $failures -eq 0 ]]
