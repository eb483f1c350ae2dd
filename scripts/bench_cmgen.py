"""Filament's cmgen against the exact reference and probefilter (see scripts/bench-cmgen)."""
import argparse
import json
import math
import platform
import shutil
import statistics
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import OpenEXR

FACES = ["px", "nx", "py", "ny", "pz", "nz"]  # cmgen's face files, in Vulkan face order
# A horizontal cross (4S x 3S): (row, column) of each Vulkan face.
CROSS = {0: (1, 2), 1: (1, 0), 2: (0, 1), 3: (2, 1), 4: (1, 1), 5: (1, 3)}


def read_rgb(path):
    return np.asarray(OpenEXR.File(str(path)).parts[0].channels["RGB"].pixels, dtype=np.float64)


def write_rgb(path, pixels):
    header = {"compression": OpenEXR.NO_COMPRESSION, "type": OpenEXR.scanlineimage}
    OpenEXR.File(header, {"RGB": np.ascontiguousarray(pixels, dtype=np.float32)}).write(str(path))


def strip_faces(strip):
    size = strip.shape[0]
    return [strip[:, k * size:(k + 1) * size] for k in range(6)]


def texel_solid_angles(size):
    """Exact solid angle of each texel of a face (the same for the six faces)."""
    edges = np.linspace(-1.0, 1.0, size + 1)
    x, y = np.meshgrid(edges, edges)
    a = np.arctan2(x * y, np.sqrt(x * x + y * y + 1.0))
    return a[1:, 1:] - a[:-1, 1:] - a[1:, :-1] + a[:-1, :-1]


def image_l1(faces, reference):
    """probe::imageL1: sum |out - ref| dOmega / sum |ref| dOmega over the six faces and RGB."""
    w = texel_solid_angles(reference[0].shape[0])[:, :, None]
    difference = sum((np.abs(f - r) * w).sum() for f, r in zip(faces, reference))
    magnitude = sum((np.abs(r) * w).sum() for r in reference)
    return difference / magnitude


def orientations(face):
    for turns in range(4):
        turned = np.rot90(face, turns)
        yield (turns, False), turned
        yield (turns, True), turned[:, ::-1]


def orient(face, how):
    turns, flip = how
    turned = np.rot90(face, turns)
    return turned[:, ::-1] if flip else turned


def write_cross(path, faces):
    size = faces[0].shape[0]
    cross = np.zeros((3 * size, 4 * size, 3))
    for k, (row, column) in CROSS.items():
        cross[row * size:(row + 1) * size, column * size:(column + 1) * size] = faces[k]
    write_rgb(path, cross)


def find_alignment(work):
    """Per Vulkan face, the cmgen face file and the rotation/flip that reproduce it at level 0 (a
    copy of the source), found by trying all 6 x 8 on a probe of random texels, which matches in one
    way only; refused unless every face matches closely."""
    size = 32
    source_faces = list(np.random.default_rng(1).uniform(0.1, 1.0, (6, size, size, 3)))
    write_cross(work / "random.exr", source_faces)
    run(["cmgen", "-q", f"-s{size}", "--format=exr", "-cRAW", "--no-mirror", f"--ibl-ld={work / 'random'}", str(work / "random.exr")])
    cmgen_level0 = {name: read_rgb(work / "random" / "random" / f"m0_{name}.exr") for name in FACES}
    alignment = []
    for k, face in enumerate(source_faces):
        scale = np.abs(face).mean()
        error, name, how = min((np.abs(o - face).mean() / scale, name, how)
                               for name in FACES for how, o in orientations(cmgen_level0[name]))
        if error > 2e-3:  # cmgen writes half floats: about 5e-4 relative
            sys.exit(f"bench-cmgen: no cmgen face matches Vulkan face {k} at level 0 (best {name}, error {error:.2e})")
        alignment.append((name, how, float(error)))
    print(f"bench-cmgen: cmgen's faces, in Vulkan order: {alignment}", file=sys.stderr)
    return alignment


def run(command):
    start = time.perf_counter()
    subprocess.run(command, check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    return time.perf_counter() - start


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--probefilter", required=True)
    parser.add_argument("--hdri-dir", required=True)
    parser.add_argument("--out", required=True)
    parser.add_argument("--size", type=int, default=128)
    parser.add_argument("--hdris", type=int, default=6, help="the first N HDRIs by name (with sunsky, room, checker)")
    parser.add_argument("--runs", type=int, default=5, help="timed runs of each tool, in turns")
    a = parser.parse_args()
    out = Path(a.out)
    shutil.rmtree(out, ignore_errors=True)
    work = out / "work"
    work.mkdir(parents=True)
    pf, size = a.probefilter, a.size
    version = subprocess.run(["dpkg-query", "-W", "-f=${Version}", "libfilament-tools"], capture_output=True, text=True).stdout

    probes = {}
    for name in ("sunsky", "room", "checker"):
        probes[name] = work / f"{name}.exr"
        run([pf, "synth", name, "--size", str(size), "--out", str(probes[name])])
    for path in sorted(Path(a.hdri_dir).glob("*.exr"))[:a.hdris]:
        probes[path.stem] = path

    # The tools, as whole processes: cmgen reads a cross, probefilter the face strip of the same cube.
    def cmgen(samples):
        extra = [] if samples is None else [f"--ibl-samples={samples}"]
        return lambda cross, strip, dest: ["cmgen", "-q", f"-s{size}", "--format=exr", "-cRAW", "--no-mirror", *extra,
                                           f"--ibl-ld={dest}", str(cross)]

    def fis(samples, levels):
        return lambda cross, strip, dest: [pf, "filter", str(strip), "--method", "fis", "--samples", str(samples), "--mapping",
                                           "filament", "--levels", str(levels), "--size", str(size), "--out", str(dest)]

    # cmgen's level count: from size down to 16x16.
    levels = int(math.log2(size)) - 3
    tools = {"cmgen (default: 1024 samples)": cmgen(None), "cmgen --ibl-samples=32": cmgen(32),
             "probefilter fis 32": fis(32, levels), "probefilter fis 1024": fis(1024, levels)}

    errors = {tool: [] for tool in tools}
    alignment = find_alignment(work)
    for name, path in probes.items():
        reference = work / name / "reference"
        run([pf, "reference", str(path), "--size", str(size), "--levels", str(levels), "--mapping", "filament", "--out", str(reference)])
        strip = reference / "level_0.exr"  # the source cube, as the reference saw it
        cross_path = work / name / "cross.exr"
        write_cross(cross_path, strip_faces(read_rgb(strip)))
        for tool, command in tools.items():
            dest = work / name / tool.replace(" ", "_").replace(":", "").replace("(", "").replace(")", "")
            run(command(cross_path, strip, dest))
            per_level = []
            for m in range(1, levels):
                reference_faces = strip_faces(read_rgb(reference / f"level_{m}.exr"))
                if tool.startswith("cmgen"):
                    found = {n: read_rgb(dest / cross_path.stem / f"m{m}_{n}.exr") for n in FACES}
                    tool_faces = [orient(found[n], how) for n, how, _ in alignment]
                else:
                    tool_faces = strip_faces(read_rgb(dest / f"level_{m}.exr"))
                per_level.append(image_l1(tool_faces, reference_faces))
            errors[tool].append(per_level)
        print(f"bench-cmgen: {name}: " + ", ".join(f"{t} {np.mean(e[-1]):.4f}" for t, e in errors.items()), file=sys.stderr)

    # Whole processes on the first HDRI (or the first probe), every tool once per round.
    timed = list(probes)[3] if len(probes) > 3 else list(probes)[0]
    seconds = {tool: [] for tool in tools}
    for _ in range(a.runs):
        for tool, command in tools.items():
            dest = work / "timed"
            shutil.rmtree(dest, ignore_errors=True)
            seconds[tool].append(run(command(work / timed / "cross.exr", work / timed / "reference" / "level_0.exr", dest)))

    report = {"size": size, "levels": levels, "mapping": "filament", "probes": list(probes), "timed_probe": timed,
              "cmgen_package": f"libfilament-tools {version}", "cpu": platform.processor() or platform.machine(),
              "alignment": [{"vulkan_face": k, "cmgen_face": n, "turns": how[0], "flip": how[1], "level0_error": e}
                            for k, (n, how, e) in enumerate(alignment)],
              "tools": {tool: {"image_l1": float(np.mean(errors[tool])),
                               "image_l1_per_level": [float(x) for x in np.mean(errors[tool], axis=0)],
                               "seconds_median": statistics.median(seconds[tool]), "seconds": seconds[tool]} for tool in tools}}
    (out / "report.json").write_text(json.dumps(report, indent=2) + "\n")
    lines = [f"{size}^2, levels 1..{levels - 1} (filament mapping), {len(probes)} probes; whole-process times on {timed}, "
             f"median of {a.runs} runs in turns",
             "",
             "| tool | image L1 (mean, levels >= 1) | per level | seconds (median) |",
             "|---|---|---|---|"]
    for tool, r in report["tools"].items():
        lines.append(f"| {tool} | {r['image_l1']:.4f} | {', '.join(f'{x:.4f}' for x in r['image_l1_per_level'])} | "
                     f"{r['seconds_median']:.2f} |")
    (out / "report.md").write_text("\n".join(lines) + "\n")
    print("\n".join(lines))


if __name__ == "__main__":
    main()
