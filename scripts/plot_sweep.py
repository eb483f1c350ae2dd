"""Error against time from sweep.csv and report.json (see scripts/plot-sweep)."""
import csv
import json
import math
import sys
from collections import defaultdict
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt


def load(folder):
    rows = list(csv.DictReader(open(folder / "sweep.csv")))
    report = json.load(open(folder / "report.json"))
    return rows, report


def scores(rows, level=None):
    """Per method over the image probes: mean image L1 (levels >= 1, or one level) and median time
    (of all levels, or of that level's pass-2 dispatch)."""
    errors, times, meta = defaultdict(list), defaultdict(dict), {}
    for r in rows:
        if r["probe"].startswith("impulse"):
            continue
        lv = int(r["level"])
        meta[r["method"]] = r
        if level is None:
            times[r["method"]][r["probe"]] = float(r["gpu_ms"])
        if (level is None and lv >= 1) or lv == level:
            errors[r["method"]].append(float(r["image_l1"]))
            if level is not None:
                times[r["method"]][r["probe"]] = float(r["level_gpu_ms"])
    out = {}
    for m, e in errors.items():
        t = sorted(times[m].values())
        out[m] = (sum(e) / len(e), t[len(t) // 2], meta[m])
    return out


def pareto(points):
    front, best = [], math.inf
    for name, (err, ms, _) in sorted(points.items(), key=lambda kv: kv[1][1]):
        if err < best:
            front.append((ms, err))
            best = err
    return front


def setting(meta):
    return f"bias {float(meta['bias']):g}, {meta['pyramid']}"


def ratio_text(ratios):
    fis = ratios["fis_family"] == "fis"
    compared = "FIS-32's" if fis else f"{ratios['fis_compared']}'s"
    budget = (f"at FIS-32's time: table error = {ratios['error_at_fis32_time']:.2f} x {compared}" if ratios["table_within_fis32_time"]
              else f"no table as fast as FIS-32 ({ratios['fis32_ms']:.1f} ms); the fastest ({ratios['table_ms']:.1f} ms): "
                   f"error = {ratios['error_at_fis32_time']:.2f} x {compared}")
    family = "FIS" if fis else "FIS-mix"
    return (("" if fis else "against per-level FIS mixes: ") + budget
            + f"\nat the table's time: table error = {ratios['error_at_table_time']:.2f} x {family}'s"
            + f"\nat the table's error: {family} time = "
            + (f"{ratios['fis_time_at_table_error']:.1f} x table's" if ratios["fis_time_at_table_error"]
               else f"> {family}-{ratios['fis_max_samples']} (never reaches it)")
            + (f"\n(table {ratios['table']}, FIS {ratios['fis_setting']})" if fis else ""))


def plot(ax, points, title, best_setting, ratios=(), xlabel="GPU time, all levels (ms)"):
    groups = defaultdict(list)
    for name, (err, ms, meta) in points.items():
        key = {"table": f"table ({meta['form']}{', per-level mix' if 'mix' in name else ''})", "fis": f"FIS {setting(meta)}",
               "fis-mix": f"FIS per-level mix, {setting(meta)}"}[meta["family"]]
        groups[key].append((ms, err, meta, name))
    for key, pts in sorted(groups.items()):
        pts.sort(key=lambda p: p[0])
        table = key.startswith("table")
        best, paper = key.endswith(best_setting), key.endswith("bias 1, box")
        uniform = key.startswith("FIS bias")
        style = dict(marker="*" if table else "o", markersize=11 if table else 5,
                     linewidth=2.2 if (table or best or (paper and uniform)) else 0.8,
                     alpha=1.0 if (table or best or (paper and uniform)) else 0.45)
        label = key + (" (best FIS setting)" if best else "") + (" (paper's FIS)" if paper and uniform else "")
        ax.plot([p[0] for p in pts], [p[1] for p in pts], label=label, **style)
        for ms, err, meta, name in pts:
            # A mixed table is named by the taps of its level 1 (gltf128_quadmix4), which set its time.
            count = name.rsplit("mix", 1)[1] if table and "mix" in name else str(meta["count"])
            ax.annotate(count, (ms, err), fontsize=6, xytext=(3, 3), textcoords="offset points")
    front = pareto(points)
    ax.plot([p[0] for p in front], [p[1] for p in front], "k--", linewidth=1, label="Pareto front")
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel(xlabel)
    ax.set_ylabel("image L1 vs exact reference")
    ax.set_title(title, fontsize=9)
    ax.grid(True, which="both", alpha=0.25)
    if ratios:
        text = "\n".join(ratio_text(r) for r in ratios)
        ax.text(0.02, 0.98, text, transform=ax.transAxes, fontsize=7, va="top",
                bbox=dict(facecolor="white", alpha=0.85, edgecolor="grey"))


def main(folder):
    folder = Path(folder)
    rows, report = load(folder)
    best = report["best_fis_setting"]
    device = report["device"]["name"]
    fig, ax = plt.subplots(figsize=(8, 6))
    plot(ax, scores(rows), f"{report['face_size']}^2, levels 1..{report['level_count'] - 1}, {device}", best,
         [r for r in (report.get("images_best_fis"), report.get("images_best_fis_mix")) if r])
    ax.legend(fontsize=6, loc="upper right")
    fig.tight_layout()
    fig.savefig(folder / "error_vs_time.png", dpi=130)

    levels = range(1, report["level_count"])
    cols = 3
    fig, axes = plt.subplots(math.ceil(len(levels) / cols), cols, figsize=(12, 3.6 * math.ceil(len(levels) / cols)), squeeze=False)
    for ax, level in zip(axes.flat, levels):
        # A level's own pass-2 time (the pyramid, shared by all levels, is left out).
        plot(ax, scores(rows, level), f"level {level}", best, xlabel="GPU time of this level's pass 2 (ms)")
    for ax in list(axes.flat)[len(levels):]:
        ax.axis("off")
    fig.tight_layout()
    fig.savefig(folder / "error_vs_time_per_level.png", dpi=110)
    print(f"plot-sweep: wrote {folder / 'error_vs_time.png'} and {folder / 'error_vs_time_per_level.png'}")


if __name__ == "__main__":
    main(sys.argv[1])
