#!/usr/bin/env bash
# An 8192 x 4096 equirectangular probe converts in bounded memory: peak resident set under 2 GiB.
set -euo pipefail
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
"$PROBEFILTER" synth sunsky --equirect 8192 --out "$work/big.exr" >/dev/null
python3 - "$PROBEFILTER" "$work" <<'PY'
import resource, subprocess, sys
probefilter, work = sys.argv[1:]
run = subprocess.run([probefilter, "reference", f"{work}/big.exr", "--size", "128", "--levels", "1", "--out", f"{work}/out"],
                     capture_output=True, text=True)
peak_mib = resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss / 1024
print(f"8192x4096 -> 128^2: exit {run.returncode}, peak RSS {peak_mib:.0f} MiB")
sys.exit(0 if run.returncode == 0 and peak_mib < 2048 else 1)
PY
