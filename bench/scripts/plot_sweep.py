"""Error against time from sweep.csv and report.json (see bench/scripts/plot-sweep)."""
import csv
import json
import math
import re
import sys
from collections import defaultdict
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt

# The synthetic checkerboard probe, whose levels levels.md lists apart from the judged probes.
CHECKER = "checker"


def load(folder):
    rows = list(csv.DictReader(open(folder / "sweep.csv")))
    report = json.load(open(folder / "report.json"))
    return rows, report


def scores(rows, level=None, first_level=1):
    """Per method over the image probes: mean image L1 (levels >= first_level, or one level) and median
    time (of all levels, or of that level's pass-2 dispatch)."""
    errors, times, meta = defaultdict(list), defaultdict(dict), {}
    for r in rows:
        if r["probe"].startswith("impulse"):
            continue
        lv = int(r["level"])
        meta[r["method"]] = r
        if level is None:
            times[r["method"]][r["probe"]] = float(r["gpu_ms"])
        if (level is None and lv >= first_level) or lv == level:
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


def is_fis(family):
    """FIS of any kind: the methods the FIS front is made of (not tables, nor a Charlie sweep's GGX levels)."""
    return family.startswith("fis")


def setting(meta):
    return f"bias {float(meta['bias']):g}, {meta['pyramid']}"


def ratio_text(r):
    budget = (f"at FIS-32's time ({r['fis32_ms']:.1f} ms): table error = {r['error_at_fis32_time']:.2f} x the FIS front's"
              if r["table_within_fis32_time"]
              else f"no table as fast as FIS-32 ({r['fis32_ms']:.1f} ms); the fastest ({r['table_ms']:.1f} ms): "
                   f"error = {r['error_at_fis32_time']:.2f} x the FIS front's at FIS-32's time")
    return (budget
            + f"\nat the table's time: table error = {r['error_at_table_time']:.2f} x the FIS front's"
            + "\nat the table's error: FIS front's time = "
            + (f"{r['fis_time_at_table_error']:.1f} x table's" if r["fis_time_at_table_error"]
               else f"never (front ends at {r['front_most_accurate']})")
            + f"\n(table {r['table']}; FIS front: every FIS method of the sweep)")


def plot(ax, points, title, best_setting, ratios=(), xlabel="GPU time, all levels (ms)"):
    """Error against time: every method, the FIS front and the Pareto front of all methods."""
    groups = defaultdict(list)
    for name, (err, ms, meta) in points.items():
        key = {"table": f"table ({meta['form']}{', per-level mix' if 'mix' in name else ''})", "fis": f"FIS {setting(meta)}",
               "fis-mix": f"FIS per-level mix, {setting(meta)}",
               "fis-paraboloid": f"FIS dual-paraboloid, bias {float(meta['bias']):g}",
               "ggx-levels": "GGX levels in its place"}[meta["family"]]
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
    fis_front = pareto({m: p for m, p in points.items() if is_fis(p[2]["family"])})
    ax.plot([p[0] for p in fis_front], [p[1] for p in fis_front], color="tab:red", linestyle=":", linewidth=1.6,
            label="FIS front (every FIS method)")
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


# The costs per output texel that do not depend on the device: the report's key, its axis label, its
# name in the tables, and a note for the plot's title.
READS = ("reads_per_texel", "trilinear reads per output texel (levels >= 1)", "reads/texel", "reads", "")
INSTRUCTIONS = ("instructions_per_texel", "RDNA2 instructions per output texel (levels >= 1)", "instructions/texel", "instructions",
                " (filter pass, hardware sampling; the paraboloid map's exact reads, its only path)")


def levels_measured(report, text):
    """`text` with "levels >= 1" as the sweep measured: every level where none is a copy (Charlie)."""
    return text if report.get("first_level", 1) > 0 else text.replace("levels >= 1", "every level")


def plot_cost(report, cost, path):
    """Error against a cost per output texel that does not depend on the device: image L1 and impulse
    L1 side by side, the FIS front of each marked."""
    key_x, xlabel, _, noun, note = cost
    xlabel = levels_measured(report, xlabel)
    fig, axes = plt.subplots(1, 2, figsize=(13, 5.5))
    for ax, key, label in zip(axes, ("image_l1", "impulse_l1"), ("image L1 vs exact reference", "impulse L1")):
        groups = defaultdict(list)
        for m in report["methods"]:
            family = m["family"]
            group = f"{family}, {setting(m)}" if is_fis(family) else family
            groups[group].append((m[key_x], m[key], m))
        for group, pts in sorted(groups.items()):
            pts.sort(key=lambda p: p[0])
            table = group == "table"
            ax.plot([p[0] for p in pts], [p[1] for p in pts], marker="*" if table else "o", markersize=10 if table else 4,
                    linestyle="none" if table else "-", linewidth=1.6 if group.startswith("fis-paraboloid") else 0.8,
                    alpha=1.0 if table else 0.5, label=group)
            if table:
                for x, err, m in pts:
                    ax.annotate(m["method"].split("_", 1)[-1], (x, err), fontsize=6, xytext=(3, 3), textcoords="offset points")
        front = pareto({m["method"]: (m[key], m[key_x], m) for m in report["methods"] if is_fis(m["family"])})
        ax.plot([p[0] for p in front], [p[1] for p in front], color="tab:red", linestyle=":", linewidth=1.6,
                label=f"FIS front over {noun}")
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlabel(xlabel)
        ax.set_ylabel(label)
        ax.grid(True, which="both", alpha=0.25)
    axes[0].legend(fontsize=6, loc="upper right")
    fig.suptitle(f"{report['face_size']}^2, levels 1..{report['level_count'] - 1}: error against {noun} per texel{note}", fontsize=9)
    fig.tight_layout()
    fig.savefig(path, dpi=120)


def front_at(front, x):
    """The front's y at x, interpolated in log y against log x; outside it, the nearer end's."""
    if x <= front[0][0]:
        return front[0][1]
    for (x0, y0), (x1, y1) in zip(front, front[1:]):
        if x1 >= x:
            t = 1.0 if x1 == x0 else (math.log(x) - math.log(x0)) / (math.log(x1) - math.log(x0))
            return math.exp(math.log(y0) + t * (math.log(y1) - math.log(y0)))
    return front[-1][1]


def front_reaches(front, y):
    """The x at which the front reaches y, interpolated the same way; None where it never does."""
    for k, (x1, y1) in enumerate(front):
        if y1 <= y:
            if k == 0:
                return x1
            x0, y0 = front[k - 1]
            t = 1.0 if y0 == y1 else (math.log(y0) - math.log(y)) / (math.log(y0) - math.log(y1))
            return math.exp(math.log(x0) + t * (math.log(x1) - math.log(x0)))
    return None


def cost_table(report, cost):
    """Every table against the FIS front over a cost per texel that does not depend on the device, per
    error measure: its error over the front's at the table's cost, and the front's cost over the
    table's at the table's error."""
    key_x, _, column, noun, _ = cost
    lines = [f"| table | {column} | image L1 | / FIS front's at that cost | front's {noun} at that error | impulse L1 | "
             f"/ FIS front's at that cost | front's {noun} at that error |", "|---|---|---|---|---|---|---|---|"]
    fronts = {key: pareto({m["method"]: (m[key], m[key_x], m) for m in report["methods"] if is_fis(m["family"])})
              for key in ("image_l1", "impulse_l1")}
    for m in sorted((m for m in report["methods"] if m["family"] == "table"), key=lambda m: m[key_x]):
        cells = [f"`{m['method']}`", f"{m[key_x]:.1f}" if key_x == "reads_per_texel" else f"{m[key_x]:.0f}"]
        for key, front in fronts.items():
            reaches = front_reaches(front, m[key])
            cells += [f"{m[key]:.4f}", f"{m[key] / front_at(front, m[key_x]):.3f}",
                      "never" if reaches is None else f"{reaches / m[key_x]:.2f}x"]
        lines.append("| " + " | ".join(cells) + " |")
    return "\n".join(lines) + "\n"


def instructions_markdown(report, instructions):
    """instructions.md: every table against the FIS front over instructions per texel, then every
    method's cost."""
    device = instructions["device"]
    lines = [levels_measured(report, "Instructions per output texel of levels >= 1")
             + f", from the compiled filter shaders on {device['name']} "
             f"({device['driver']}): the code outside the tap or sample loop once, the runtime loop per tap or sample "
             "(bench/shader_stats/shader_stats; a table's levels handed to FIS count a tap per sample). Hardware sampling, "
             "which a GPU runs; FIS on the dual-paraboloid map reads a buffer exactly, its only path. The filter pass alone: "
             "the pyramid pass is not counted.", "",
             cost_table(report, INSTRUCTIONS),
             "| method | family | shader loop | reads/texel | taps or samples/texel | instructions/texel | image L1 | impulse L1 |",
             "|---|---|---|---|---|---|---|---|"]
    for m in sorted(report["methods"], key=lambda m: m["instructions_per_texel"]):
        lines.append(f"| `{m['method']}` | {m['family']} | `{m['loop']}` | {m['reads_per_texel']:.1f} | "
                     f"{m['shader_taps_per_texel']:.1f} | {m['instructions_per_texel']:.0f} | {m['image_l1']:.4f} | "
                     f"{m['impulse_l1']:.4f} |")
    return "\n".join(lines) + "\n"


def hand_offs(tables, fis, family, setting, error, best_within):
    """The levels each table should hand to FIS (TableLevel::fisSamples): those where FIS with bias 0 on the
    table's pyramid, no slower at that level, is more accurate on most probes (the checkerboard aside); the
    count is the one that wins most often. `probefit export` records it."""
    lines = []
    for table in tables:
        same = [f for f in fis if family[f] == "fis" and setting[f] == f"bias 0, {setting[table].split(', ')[1]}"]
        for level in sorted({level for (probe, level) in error[table]}):
            probes = [probe for (probe, m) in error[table] if m == level and probe != CHECKER]
            winners = [best_within(table, same, probe, level) for probe in probes]
            winners = [w for w, probe in zip(winners, probes) if w and error[w][(probe, level)] < error[table][(probe, level)]]
            if probes and 2 * len(winners) > len(probes):
                count = max(set(winners), key=winners.count)
                samples = int(re.match(r"fis(\d+)", count).group(1))
                lines.append(f"- `{table}` level {level}: FIS {samples} (bias 0) wins on {len(winners)} of {len(probes)} probes: "
                             f"`probefit export {table}.json --fis-level {level}:{samples} --out {table}`")
    head = ["", "Hand-offs: where FIS at bias 0 on the table's pyramid, no slower at that level, is the more accurate on "
            "most probes, the table should hand the level to it (`TableLevel::fisSamples`; the command records it)."]
    return head + [""] + (lines or ["- none"])


def level_table(rows, best_setting, first_level):
    """Per table, level and probe: the table's image L1 against FIS whose pass 2 for that level is no
    slower than the table's (level_gpu_ms), and every pair it loses: against the most accurate FIS
    method of the sweep for that very probe and level (any sample count, bias and pyramid), and
    against FIS at the sweep's best setting (one bias and pyramid for every probe, as an engine
    ships it: report.json's best_fis_setting), its most accurate sample count within the time.
    Judged on the real probes, the impulses and the synthetic sun-and-sky and room; the synthetic
    checkerboard, whose rough levels the exact filter averages almost to grey, is listed apart with
    its absolute errors."""
    error, level_ms, family, setting = defaultdict(dict), defaultdict(dict), {}, {}
    for r in rows:
        level = int(r["level"])
        if level < first_level:
            continue
        family[r["method"]] = r["family"]
        setting[r["method"]] = f"bias {float(r['bias']):g}, {r['pyramid']}"
        level_ms[r["method"]][level] = float(r["level_gpu_ms"])
        error[r["method"]][(r["probe"], level)] = float(r["image_l1"])
    fis = [m for m in family if is_fis(family[m])]
    at_best = [m for m in fis if family[m] == "fis" and setting[m] == best_setting]
    tables = sorted((m for m in family if family[m] == "table"), key=lambda m: sum(level_ms[m].values()))

    def best_within(table, methods, probe, level):
        within = [f for f in methods if level_ms[f][level] <= level_ms[table][level]]
        return min(within, key=lambda f: error[f][(probe, level)]) if within else None

    def losses(table, methods):
        lost, pairs = [], 0
        for (probe, level), e in sorted(error[table].items(), key=lambda kv: (kv[0][1], kv[0][0])):
            best = best_within(table, methods, probe, level)
            if probe == CHECKER or best is None:
                continue
            pairs += 1
            if e > error[best][(probe, level)]:
                lost.append(f"{probe} {level}: {e:.4f} / {error[best][(probe, level)]:.4f} `{best}`")
        return pairs, lost

    lines = ["Per level and probe, each table against FIS whose pass 2 for that level takes no longer than the table's "
             "(`level_gpu_ms`); image L1 (impulse probes: their image L1), on every probe but the synthetic checkerboard "
             "(below). *Any setting*: the most accurate FIS method of the sweep for that probe and level (every sample "
             "count, bias and pyramid). *Best setting*: FIS at the sweep's best single setting "
             f"({best_setting}, as an engine ships one), its most accurate sample count.", "",
             "| table | level-probe pairs | lost to FIS, any setting | lost to FIS, best setting | losses, any setting (probe, "
             "level: table / FIS, method) | losses, best setting |", "|---|---|---|---|---|---|"]
    for table in tables:
        pairs, lost = losses(table, fis)
        pairs_best, lost_best = losses(table, at_best)
        lines.append(f"| `{table}` | {pairs} | {len(lost)} | {len(lost_best)} of {pairs_best} | {'; '.join(lost) or '-'} | "
                     f"{'; '.join(lost_best) or '-'} |")
    lines += hand_offs(tables, fis, family, setting, error, best_within)
    levels = sorted({level for (probe, level) in error[tables[0]] if probe == CHECKER}) if tables else []
    if levels:
        lines += ["", "The synthetic checkerboard apart: at rough levels the exact filter averages its pattern almost to grey, "
                  "so every method's error there is small, and a table's sharp central taps alias what FIS's blurry coarse "
                  "reads smooth away. Per level: the table's image L1 / the most accurate FIS's within the table's time "
                  "(any setting); **bold** where FIS is the more accurate.", "",
                  "| table | " + " | ".join(f"level {m}" for m in levels) + " |", "|---|" + "---|" * len(levels)]
        for table in tables:
            cells = []
            for m in levels:
                e, best = error[table][(CHECKER, m)], best_within(table, fis, CHECKER, m)
                cell = f"{e:.4f} / {error[best][(CHECKER, m)]:.4f}" if best else f"{e:.4f} / -"
                cells.append(f"**{cell}**" if best and e > error[best][(CHECKER, m)] else cell)
            lines.append(f"| `{table}` | " + " | ".join(cells) + " |")
    return "\n".join(lines) + "\n"


def main(folder):
    folder = Path(folder)
    rows, report = load(folder)
    best = report["best_fis_setting"]
    device = report["device"]["name"]
    fig, ax = plt.subplots(figsize=(8, 6))
    first = report.get("first_level", 1)
    plot(ax, scores(rows, first_level=first),
         f"{report['face_size']}^2, levels {first}..{report['level_count'] - 1}, {report.get('lobe', 'ggx')} lobe, {device}", best,
         [r for r in (report.get("images"),) if r])
    ax.legend(fontsize=6, loc="upper right")
    fig.tight_layout()
    fig.savefig(folder / "error_vs_time.png", dpi=130)

    levels = range(first, report["level_count"])
    cols = 3
    fig, axes = plt.subplots(math.ceil(len(levels) / cols), cols, figsize=(12, 3.6 * math.ceil(len(levels) / cols)), squeeze=False)
    for ax, level in zip(axes.flat, levels):
        # A level's own pass-2 time (the pyramid, shared by all levels, is left out).
        plot(ax, scores(rows, level), f"level {level}", best, xlabel="GPU time of this level's pass 2 (ms)")
    for ax in list(axes.flat)[len(levels):]:
        ax.axis("off")
    fig.tight_layout()
    fig.savefig(folder / "error_vs_time_per_level.png", dpi=110)
    plot_cost(report, READS, folder / "error_vs_reads.png")
    (folder / "reads.md").write_text(cost_table(report, READS))
    (folder / "levels.md").write_text(level_table(rows, best, report.get("first_level", 1)))
    written = ["error_vs_time.png", "error_vs_time_per_level.png", "error_vs_reads.png", "reads.md", "levels.md"]
    # bench/scripts/shader-stats --sweep DIR writes it (bench/scripts/sweep runs it).
    if (folder / "instructions.json").exists():
        instructions = json.load(open(folder / "instructions.json"))
        costs = {m["method"]: m for m in instructions["methods"]}
        for m in report["methods"]:
            m.update(loop=costs[m["method"]]["loop"], instructions_per_texel=costs[m["method"]]["instructions_per_texel"])
        plot_cost(report, INSTRUCTIONS, folder / "error_vs_instructions.png")
        (folder / "instructions.md").write_text(instructions_markdown(report, instructions))
        written += ["error_vs_instructions.png", "instructions.md"]
    else:
        print(f"plot-sweep: no {folder / 'instructions.json'} (bench/scripts/shader-stats --family navi21 --sweep {folder}): "
              "no instruction plot", file=sys.stderr)
    print(f"plot-sweep: wrote {', '.join(str(folder / name) for name in written)}")


if __name__ == "__main__":
    main(sys.argv[1])
