#!/usr/bin/env python3
"""Markdown tables from criterion's output (issue 12; standard library only).

    python3 scripts/criterion_table.py [CRITERION_DIR]

CRITERION_DIR defaults to $CARGO_TARGET_DIR/criterion or target/criterion.
For every benchmark it reads `<id>/new/benchmark.json` (ids, throughput) and
`<id>/new/sample.json` (the measured samples: iteration counts and total
times) and takes the time per iteration of each sample (per element when a
throughput is set, e.g. per ray). Over the samples of one run it reports
min / median / max; ratios inside a group are min/min, median/median and
max/max against the group's baseline (`segment` for `per_ray`, `serial` for
`frame`, `abvs` for `abuffer`, `sample` for `slice`, else the first line).

Output: the `per_ray` groups as one scene × method matrix (median µs per ray
and the ratio to `segment`), then one table per other group family.
Benchmarks of the other bench targets (ia_ops, …) are listed only with
--all.
"""

import json
import os
import statistics
import sys

BASELINES = {"per_ray": "segment", "frame": "serial", "abuffer": "abvs", "slice": "sample"}
FAMILIES = ["per_ray", "frame", "abuffer", "slice"]


def load(root):
    out = []
    for dirpath, _dirs, files in os.walk(root):
        if os.path.basename(dirpath) != "new" or "benchmark.json" not in files:
            continue
        if "sample.json" not in files:
            continue
        with open(os.path.join(dirpath, "benchmark.json")) as f:
            bench = json.load(f)
        with open(os.path.join(dirpath, "sample.json")) as f:
            sample = json.load(f)
        per = 1.0
        tp = bench.get("throughput") or {}
        for key in ("Elements", "Bytes", "BytesDecimal"):
            if key in tp and tp[key]:
                per = float(tp[key])
        times = [t / n / per for t, n in zip(sample["times"], sample["iters"]) if n > 0]
        if not times:
            continue
        out.append(
            {
                "group": bench["group_id"],
                "function": bench.get("function_id") or "",
                "value": bench.get("value_str") or "",
                "per": per,
                "ns": [min(times), statistics.median(times), max(times)],
                "samples": len(times),
            }
        )
    return out


def fmt_time(ns):
    if ns >= 1e6:
        return f"{ns / 1e6:.2f} ms"
    if ns >= 1e3:
        return f"{ns / 1e3:.1f} µs"
    return f"{ns:.0f} ns"


def ratio(a, b):
    return [x / y if y > 0 else float("nan") for x, y in zip(a, b)]


def family(group):
    return group.split("/", 1)[0]


def per_ray_matrix(rows):
    groups = {}
    for r in rows:
        groups.setdefault(r["group"].split("/", 1)[1], {})[r["function"]] = r
    methods = []
    for g in groups.values():
        for m in g:
            if m not in methods:
                methods.append(m)
    order = [
        "sphere", "segment", "linear-taylor", "linear-bottom-up", "linear-mixed",
        "quadratic-taylor", "quadratic-bottom-up", "quadratic-mixed", "interval",
        "affine", "scalis-quadratic",
    ]
    methods.sort(key=lambda m: order.index(m) if m in order else len(order))
    print("Median time per ray (µs) and, in parentheses, the ratio of medians to `segment` "
          "on the same rays (— : method not applicable to the scene, or left out because one pass "
          "over the rays took more than 2 s; the bench names those on stderr).\n")
    print("| scene | " + " | ".join(methods) + " |")
    print("| --- |" + " ---: |" * len(methods))
    for scene, g in groups.items():
        base = g.get("segment")
        cells = []
        for m in methods:
            r = g.get(m)
            if r is None:
                cells.append("—")
                continue
            med = r["ns"][1] / 1e3
            if base is not None:
                cells.append(f"{med:.1f} ({r['ns'][1] / base['ns'][1]:.2f})")
            else:
                cells.append(f"{med:.1f}")
        print(f"| {scene} | " + " | ".join(cells) + " |")
    print()
    print("<details><summary>min / median / max per ray, every method and scene</summary>\n")
    list_table(rows, "segment")
    print("\n</details>\n")


def list_table(rows, baseline):
    print("| group | benchmark | samples | min | median | max | ratio to baseline (min / median / max) |")
    print("| --- | --- | ---: | ---: | ---: | ---: | --- |")
    groups = {}
    for r in rows:
        groups.setdefault(r["group"], []).append(r)
    for g, rs in groups.items():
        base = next((r for r in rs if r["function"] == baseline), rs[0])
        for r in rs:
            name = r["function"] + (f" ({r['value']})" if r["value"] else "")
            if r is base:
                rat = f"baseline (`{base['function']}`)"
            else:
                a, m, b = ratio(r["ns"], base["ns"])
                rat = f"{a:.2f} / **{m:.2f}** / {b:.2f}"
            t = [fmt_time(x) for x in r["ns"]]
            print(f"| {g} | {name} | {r['samples']} | {t[0]} | {t[1]} | {t[2]} | {rat} |")


def main(argv):
    args = [a for a in argv[1:] if a != "--all"]
    show_all = "--all" in argv[1:]
    root = args[0] if args else os.path.join(os.environ.get("CARGO_TARGET_DIR", "target"), "criterion")
    if not os.path.isdir(root):
        print(f"error: no criterion output at {root} (run cargo bench first)", file=sys.stderr)
        return 1
    rows = load(root)
    if not rows:
        print(f"error: no benchmark results under {root}", file=sys.stderr)
        return 1
    rows.sort(key=lambda r: (r["group"], r["function"], r["value"]))
    fams = {}
    for r in rows:
        fams.setdefault(family(r["group"]), []).append(r)
    printed = False
    if "per_ray" in fams:
        print("### Per-ray cost of every method (criterion `per_ray`)\n")
        per_ray_matrix(fams["per_ray"])
        printed = True
    for f in FAMILIES[1:]:
        if f in fams:
            print(f"### `{f}` (criterion)\n")
            list_table(fams[f], BASELINES[f])
            print()
            printed = True
    if show_all:
        for f, rs in fams.items():
            if f not in FAMILIES:
                print(f"### `{f}` (criterion)\n")
                list_table(rs, None)
                print()
                printed = True
    if not printed:
        print("error: none of the per_ray/frame/abuffer/slice benchmarks have results", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
