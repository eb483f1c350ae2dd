"""Filament's cmgen against the exact reference and probefilter (see bench/scripts/cmgen)."""
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


def face_directions(size):
    """Unit direction of every texel centre, (6, size, size, 3) indexed [face, j, i] (core's
    faceUvToCubePoint and texelCentreUv)."""
    uv = (2.0 * np.arange(size) + 1.0) / size - 1.0
    u, v = np.meshgrid(uv, uv)  # [j, i]
    one = np.ones_like(u)
    points = [(one, -v, -u), (-one, -v, u), (u, one, v), (u, -one, -v), (u, -v, one), (-u, -v, -one)]
    d = np.stack([np.stack(p, axis=-1) for p in points])
    return d / np.linalg.norm(d, axis=-1, keepdims=True)


def exact_reference(sources, directions, alphas):
    """probe::referenceLevel of each source cube (a list of six faces) at the output directions (K, 3),
    for each alpha: the GGX kernel D(R.h) max(R.l, 0) (ggx.h's form) times the source texels' solid
    angles, normalized. Returns (len(sources), len(alphas), K, 3)."""
    size = sources[0][0].shape[0]
    l = face_directions(size).reshape(-1, 3)
    w = np.tile(texel_solid_angles(size).reshape(-1), 6)
    radiance = np.concatenate([np.concatenate([f.reshape(-1, 3) for f in faces]) for faces in sources], axis=1) * w[:, None]
    out = np.zeros((len(alphas), len(directions), 3 * len(sources)))
    for begin in range(0, len(directions), 64):
        R = directions[begin:begin + 64]
        cos = R @ l.T
        d2 = np.maximum(2.0 - 2.0 * cos, 0.0)  # |R - l|^2 of unit vectors
        half = (1.0 + cos) * 0.5
        for k, alpha in enumerate(alphas):
            a2 = alpha * alpha
            q = d2 * 0.25 + half * a2
            kernel = np.where(cos > 0.0, a2 / (np.pi * q * q) * cos, 0.0)
            out[k, begin:begin + 64] = (kernel @ radiance) / (kernel @ w)[:, None]
    return out.reshape(len(alphas), len(directions), len(sources), 3).transpose(2, 0, 1, 3)


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
            sys.exit(f"bench/scripts/cmgen: no cmgen face matches Vulkan face {k} at level 0 (best {name}, error {error:.2e})")
        alignment.append((name, how, float(error)))
    print(f"bench/scripts/cmgen: cmgen's faces, in Vulkan order: {alignment}", file=sys.stderr)
    return alignment


def filament_alpha(level, levels):
    """GGX alpha of a level of probefilter's filament mapping (core's levelRoughness): lod = r (2 - r)
    with lod = level / (levels - 1), alpha = r^2."""
    x = level / (levels - 1)
    return (x / (1.0 + math.sqrt(1.0 - x))) ** 2


# The roughness check: alpha = the mapping's x 2^(k/8), k = -8..8, then a parabola through the best
# three in log alpha; the texels of a level it compares (all of a level that has fewer).
ALPHA_STEPS = [2.0 ** (k / 8.0) for k in range(-8, 9)]
MAPPING_STEP = 8  # ALPHA_STEPS[MAPPING_STEP] = 1
FIT_TEXELS = 384
# The closest alpha must lie within this factor of the mapping's. It tells the filament mapping at 7
# levels from the same mapping at 6 or 8 levels (1.38x to 2.9x apart at every level of 128^2) and from
# the other mappings that differ by as much; it leaves room for the blur that filtered importance
# sampling adds to the smallest lobes (it reads each sample from a coarser mip).
ALPHA_TOLERANCE = 1.25


def fit_roughness(probes, references, outputs, levels):
    """Per tool of `outputs` ({tool: {probe: levels of faces}}) and level >= 1: the GGX alpha whose
    exact reference is closest (solid-angle weighted L1 over stratified texels, averaged over the
    probes) to the tool's output, scanned around the filament mapping's alpha. The scan's own
    reference is checked against probefilter's at the mapping's alpha first."""
    rng = np.random.default_rng(2)
    fits = {tool: [] for tool in outputs}
    for m in range(1, levels):
        size = references[probes[0]][m][0].shape[0]
        texels = np.arange(6 * size * size)
        if len(texels) > FIT_TEXELS:
            texels = rng.choice(texels, FIT_TEXELS, replace=False)
        directions = face_directions(size).reshape(-1, 3)[texels]
        weights = np.tile(texel_solid_angles(size).reshape(-1), 6)[texels][:, None]
        expected = filament_alpha(m, levels)
        alphas = [expected * step for step in ALPHA_STEPS]
        scans = exact_reference([references[name][0] for name in probes], directions, alphas)
        for name, scan in zip(probes, scans):
            own = np.concatenate([f.reshape(-1, 3) for f in references[name][m]])[texels]
            check = (np.abs(scan[MAPPING_STEP] - own) * weights).sum() / (np.abs(own) * weights).sum()
            if check > 1e-4:
                sys.exit(f"bench/scripts/cmgen: the roughness scan's reference differs from probefilter's at level {m} of {name} "
                         f"(L1 {check:.2e})")
        for tool, levels_of in outputs.items():
            losses = np.zeros(len(alphas))
            for name, scan in zip(probes, scans):
                found = np.concatenate([f.reshape(-1, 3) for f in levels_of[name][m]])[texels]
                losses += [(np.abs(found - r) * weights).sum() / (np.abs(r) * weights).sum() / len(probes) for r in scan]
            k = int(np.argmin(losses))
            if k in (0, len(alphas) - 1):
                sys.exit(f"bench/scripts/cmgen: {tool}'s level {m} is closest to alpha {alphas[k]:.4g}, the end of the scan "
                         f"({alphas[0]:.4g} to {alphas[-1]:.4g}) around the filament mapping's {expected:.4g}")
            # The parabola's vertex through (log alpha, L1) at k - 1, k, k + 1 (equal steps).
            a, b, c = losses[k - 1:k + 2]
            offset = 0.5 * (a - c) / (a - 2.0 * b + c) if a - 2.0 * b + c > 0.0 else 0.0
            fitted = expected * 2.0 ** ((k - MAPPING_STEP + offset) / 8.0)
            fits[tool].append({"level": m, "filament_alpha": expected, "closest_alpha": fitted, "ratio": fitted / expected,
                               "l1_at_closest_step": float(losses[k]), "l1_at_filament_alpha": float(losses[MAPPING_STEP])})
            print(f"bench/scripts/cmgen: {tool}, level {m}: closest alpha {fitted:.4g}, the filament mapping's {expected:.4g} "
                  f"(ratio {fitted / expected:.3f}; L1 {losses[k]:.4f} at the closest step, {losses[MAPPING_STEP]:.4f} at the "
                  "mapping's)", file=sys.stderr)
    for tool, per_level in fits.items():
        bad = [f for f in per_level if not 1.0 / ALPHA_TOLERANCE <= f["ratio"] <= ALPHA_TOLERANCE]
        if bad:
            sys.exit(f"bench/scripts/cmgen: {tool}'s roughness is not the filament mapping's within {ALPHA_TOLERANCE}x at level(s) "
                     + ", ".join(f"{f['level']} (alpha {f['closest_alpha']:.4g}, expected {f['filament_alpha']:.4g})" for f in bad))
    return fits


def run(command):
    start = time.perf_counter()
    subprocess.run(command, check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    return time.perf_counter() - start


def read_levels(folder, levels):
    return [strip_faces(read_rgb(folder / f"level_{m}.exr")) for m in range(levels)]


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--probefilter", required=True)
    parser.add_argument("--hdri-dir", required=True)
    parser.add_argument("--out", required=True)
    parser.add_argument("--size", type=int, default=128)
    parser.add_argument("--table", default="filament128_quad8", help="probefilter's table (its filament mapping, size and levels)")
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

    # probefilter's default level count, log2(size): down to 2x2, which cmgen reaches with
    # --ibl-min-lod-size=2 (its default, 16, stops at 16x16).
    levels = int(math.log2(size))
    min_lod_size = size >> (levels - 1)

    # The tools, as whole processes: cmgen reads a cross, probefilter the face strip of the same cube.
    def cmgen(samples):
        extra = [] if samples is None else [f"--ibl-samples={samples}"]
        return lambda cross, strip, dest: ["cmgen", "-q", f"-s{size}", "--format=exr", "-cRAW", "--no-mirror",
                                           f"--ibl-min-lod-size={min_lod_size}", *extra, f"--ibl-ld={dest}", str(cross)]

    def probefilter(*method):
        return lambda cross, strip, dest: [pf, "filter", str(strip), *method, "--mapping", "filament", "--levels", str(levels),
                                           "--size", str(size), "--out", str(dest)]

    default_cmgen, control = "cmgen (default: 1024 samples)", "probefilter fis 1024"
    table_tool = f"probefilter table {a.table}"
    tools = {default_cmgen: cmgen(None), "cmgen --ibl-samples=32": cmgen(32),
             "probefilter fis 32": probefilter("--method", "fis", "--samples", "32"),
             control: probefilter("--method", "fis", "--samples", "1024"),
             table_tool: probefilter("--method", "table", "--table", a.table)}

    errors = {tool: [] for tool in tools}
    device = None
    alignment = find_alignment(work)
    references, cmgen_levels, control_levels = {}, {}, {}
    for name, path in probes.items():
        reference = work / name / "reference"
        run([pf, "reference", str(path), "--size", str(size), "--levels", str(levels), "--mapping", "filament", "--out", str(reference)])
        references[name] = read_levels(reference, levels)
        strip = reference / "level_0.exr"  # the source cube, as the reference saw it
        cross_path = work / name / "cross.exr"
        write_cross(cross_path, references[name][0])
        for tool, command in tools.items():
            dest = work / name / tool.replace(" ", "_").replace(":", "").replace("(", "").replace(")", "")
            run(command(cross_path, strip, dest))
            if tool.startswith("cmgen"):
                found = [{n: read_rgb(dest / cross_path.stem / f"m{m}_{n}.exr") for n in FACES} for m in range(levels)]
                if (dest / cross_path.stem / f"m{levels}_px.exr").exists():
                    sys.exit(f"bench/scripts/cmgen: cmgen wrote more than {levels} levels with --ibl-min-lod-size={min_lod_size}")
                tool_levels = [[orient(f[n], how) for n, how, _ in alignment] for f in found]
                if tool == default_cmgen:
                    cmgen_levels[name] = tool_levels
            else:
                tool_levels = read_levels(dest, levels)
                if tool == control:
                    control_levels[name] = tool_levels
                if tool == table_tool:
                    table_report = json.loads((dest / "report.json").read_text())
                    device = table_report["device"]
                    table = table_report["table"]
                    if (table["mapping"], table["face_size"], table["level_count"]) != ("filament", size, levels):
                        sys.exit(f"bench/scripts/cmgen: {a.table} is not a filament table of {size}^2 with {levels} levels: {table}")
            errors[tool].append([image_l1(tool_levels[m], references[name][m]) for m in range(1, levels)])
        print(f"bench/scripts/cmgen: {name}: " + ", ".join(f"{t} {np.mean(e[-1]):.4f}" for t, e in errors.items()), file=sys.stderr)

    # cmgen's roughness per level, measured on the synthetic probes; probefilter's FIS-1024, whose
    # alpha is the mapping's by construction, shows what the scan resolves.
    synthetic = ["sunsky", "room", "checker"]
    roughness = fit_roughness(synthetic, references, {default_cmgen: cmgen_levels, control: control_levels}, levels)

    # Whole processes on the first HDRI (or the first probe), every tool once per round.
    timed = list(probes)[3] if len(probes) > 3 else list(probes)[0]
    seconds = {tool: [] for tool in tools}
    for _ in range(a.runs):
        for tool, command in tools.items():
            dest = work / "timed"
            shutil.rmtree(dest, ignore_errors=True)
            seconds[tool].append(run(command(work / timed / "cross.exr", work / timed / "reference" / "level_0.exr", dest)))

    report = {"size": size, "levels": levels, "cmgen_min_lod_size": min_lod_size, "mapping": "filament", "probes": list(probes),
              "timed_probe": timed, "cmgen_package": f"libfilament-tools {version}", "cpu": platform.processor() or platform.machine(),
              "device": device,
              "alignment": [{"vulkan_face": k, "cmgen_face": n, "turns": how[0], "flip": how[1], "level0_error": e}
                            for k, (n, how, e) in enumerate(alignment)],
              "roughness_per_level": roughness,
              "tools": {tool: {"image_l1": float(np.mean(errors[tool])),
                               "image_l1_per_level": [float(x) for x in np.mean(errors[tool], axis=0)],
                               "seconds_median": statistics.median(seconds[tool]), "seconds": seconds[tool]} for tool in tools}}
    (out / "report.json").write_text(json.dumps(report, indent=2) + "\n")
    level_names = ", ".join(str(m) for m in range(1, levels))
    lines = [f"{size}^2, levels 1..{levels - 1} (filament mapping; cmgen --ibl-min-lod-size={min_lod_size}), {len(probes)} probes; "
             f"whole-process times on {timed}, median of {a.runs} runs in turns",
             "",
             f"| tool | image L1 (mean, levels >= 1) | levels {level_names} | seconds (median) |",
             "|---|---|---|---|"]
    for tool, r in report["tools"].items():
        lines.append(f"| {tool} | {r['image_l1']:.4f} | {', '.join(f'{x:.4f}' for x in r['image_l1_per_level'])} | "
                     f"{r['seconds_median']:.2f} |")
    lines += ["", f"Roughness per level: the alpha whose exact reference is closest to the tool's output on sunsky, room and "
                  f"checker (required within {ALPHA_TOLERANCE}x of the filament mapping's):",
              "",
              f"| level | filament alpha | {default_cmgen}: closest alpha | ratio | {control}: closest alpha | ratio |",
              "|---|---|---|---|---|---|"]
    for f, g in zip(roughness[default_cmgen], roughness[control]):
        lines.append(f"| {f['level']} | {f['filament_alpha']:.4g} | {f['closest_alpha']:.4g} | {f['ratio']:.3f} | "
                     f"{g['closest_alpha']:.4g} | {g['ratio']:.3f} |")
    (out / "report.md").write_text("\n".join(lines) + "\n")


if __name__ == "__main__":
    main()
