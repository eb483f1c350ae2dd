#!/usr/bin/env bash
# Memory stays bounded by what one input needs:
# - an 8192 x 4096 equirectangular probe converts with a peak resident set under 2 GiB;
# - at the limits: a probe at the pixel limit (16384 x 8192, 1.5 GiB as float RGB) to the largest face
#   size (reference --size 2048, level 0 only: the image is freed once it is a cube), and a scene of
#   1024 materials (the most a scene may have) drawn as spheres, each under 2 GiB;
# - a scene of six 512^2 probes (no spheres) peaks within 48 MiB of the same scene with two (the first
#   warms the allocator), since `run` holds one probe's images at a time (holding them all adds the
#   images of each probe, about 23 MiB at 512^2; each scene runs three times and its least peak
#   counts, as the driver's own share varies).
set -euo pipefail
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
"$PROBEFILTER" synth sunsky --equirect 8192 --out "$work/big.exr" >/dev/null
"$PROBEFILTER" synth sky --size 512 --out "$work/sky.exr" >/dev/null
"$PROBEFILTER" synth sunsky --equirect 16384 --out "$work/limit.exr" >/dev/null
python3 - "$PROBEFILTER" "$work" <<'PY'
import json, os, subprocess, sys
probefilter, work = sys.argv[1:]

def peak_mib(args):
    """Runs probefilter with args; its own peak resident set (wait4: this child's usage alone)."""
    child = subprocess.Popen([probefilter, *args], stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    _, status, usage = os.wait4(child.pid, 0)
    if os.waitstatus_to_exitcode(status) != 0:
        sys.exit(f"FAIL: probefilter {' '.join(args)} exited {os.waitstatus_to_exitcode(status)}")
    return usage.ru_maxrss / 1024

big = peak_mib(["reference", f"{work}/big.exr", "--size", "128", "--levels", "1", "--out", f"{work}/out"])
print(f"8192x4096 -> 128^2: peak RSS {big:.0f} MiB")
limit = peak_mib(["reference", f"{work}/limit.exr", "--size", "2048", "--levels", "1", "--out", f"{work}/out"])
print(f"16384x8192 -> 2048^2: peak RSS {limit:.0f} MiB")
materials = [{"name": f"m{k}", "roughness": (k % 11) / 10, "metallic": k % 2} for k in range(1024)]
with open(f"{work}/spheres.json", "w") as f:
    json.dump({"probes": [{"name": "sky", "image": "sky.exr", "face_size": 64}], "materials": materials, "outputs": {"spheres": True}}, f)
spheres = peak_mib(["run", f"{work}/spheres.json", "--out", f"{work}/spheres"])
print(f"1024 materials as spheres: peak RSS {spheres:.0f} MiB")

scenes = {}
for count in (2, 6):
    probes = [{"name": f"p{k}", "image": "sky.exr", "face_size": 512, "method": "fis", "samples": 8} for k in range(count)]
    materials = [{"name": f"m{k}", "roughness": 0.5, "probe": f"p{k}"} for k in range(count)]
    with open(f"{work}/scene{count}.json", "w") as f:
        json.dump({"probes": probes, "materials": materials}, f)
    # The Vulkan driver's own allocations vary by tens of MiB from run to run (lavapipe's threads):
    # the least of three runs is the probes' share.
    scenes[count] = min(peak_mib(["run", f"{work}/scene{count}.json", "--out", f"{work}/run{count}"]) for _ in range(3))
print(f"run, 512^2 probes: two {scenes[2]:.0f} MiB, six {scenes[6]:.0f} MiB")
sys.exit(0 if max(big, limit, spheres) < 2048 and scenes[6] - scenes[2] < 48 else 1)
PY
