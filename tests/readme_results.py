#!/usr/bin/env python3
"""The README's results table agrees with the sweep reports it is taken from: each number, as
printed (its decimals), is the report's value rounded (docs/reports/sweep/report.json for the lavapipe rows,
docs/reports/sweep-h200/report.json for the H200 row)."""
import json
import pathlib
import sys

root = pathlib.Path(__file__).resolve().parent.parent
# The table's columns: the sweep's method names.
columns = ["gltf128_quad8", "gltf128_quadmix8lean", "fis32-bias0-bspline", "fis1024-bias0.5-bspline"]
# Row label: (report, key).
rows = {
    "image L1": ("docs/reports/sweep/report.json", "image_l1"),
    "impulse L1": ("docs/reports/sweep/report.json", "impulse_l1"),
    "reads per texel": ("docs/reports/sweep/report.json", "reads_per_texel"),
    "lavapipe ms, all levels": ("docs/reports/sweep/report.json", "gpu_ms"),
    "NVIDIA H200 ms, all levels": ("docs/reports/sweep-h200/report.json", "gpu_ms"),
}


def methods(report):
    return {m["method"]: m for m in json.loads((root / report).read_text())["methods"]}


def main():
    lines = (root / "README.md").read_text().splitlines()
    header = next((line for line in lines if line.startswith("| 128^2")), None)
    if header is None:
        sys.exit("README.md: no results table (a row starting '| 128^2')")
    failures, seen = [], set()
    for line in lines:
        cells = [c.strip() for c in line.strip().strip("|").split("|")]
        if cells[0] not in rows:
            continue
        seen.add(cells[0])
        report, key = rows[cells[0]]
        measured = methods(report)
        for method, text in zip(columns, cells[1:]):
            decimals = len(text.split(".")[1]) if "." in text else 0
            value = measured[method][key]
            if abs(float(text) - value) > 0.5 * 10 ** -decimals + 1e-9:
                failures.append(f"{cells[0]}, {method}: README {text}, {report} {value:.6g}")
    missing = set(rows) - seen
    if missing:
        failures.append(f"rows missing from the README's table: {sorted(missing)}")
    for f in failures:
        print("FAIL", f)
    if failures:
        sys.exit(1)
    print(f"README results: {len(seen)} rows x {len(columns)} methods agree with the sweep reports")


main()
