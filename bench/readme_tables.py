#!/usr/bin/env python3
"""The tables of docs/benchmarks.md, from what bench/readme_tables.sh OUT left in OUT.

Usage: bench/readme_tables.py OUT [DOC]
Prints every table under a heading (what the script keeps as OUT/tables.md; a section that did
not run prints "(not run)"). With DOC (docs/benchmarks.md), also replaces in DOC each table
between the lines "<!-- table NAME -->" and "<!-- end table -->" by the one measured in OUT;
a table whose section did not run is left as it is, and the prose around the tables is not
touched. Numbers come from the scripts' own outputs (compare_colmap, weak_rings,
self_calibration, real_self_calibration, front_end_speed, thousand_photos) or, for the pose
table and Table 1, from the benchmark.json files pose_accuracy.sh left.
"""
import contextlib
import io
import json
import os
import re
import sys

out = sys.argv[1]


def text(name):
    path = os.path.join(out, name)
    return open(path).read() if os.path.isfile(path) else None


def markdown(header, rows):
    print("| " + " | ".join(header) + " |")
    print("|" + "---|" * len(header))
    for r in rows:
        print("| " + " | ".join(r) + " |")


def spaced_table(name, header):
    """A table the script printed as space-separated columns (first line its header)."""
    t = text(name)
    if t is None:
        print("(not run)\n")
        return
    lines = [l.split() for l in t.splitlines() if l.strip() and not l.startswith("  (kept") and not l.startswith("--")]
    rows = [f for f in lines[1:] if f[0] != lines[0][0]]
    markdown(header, rows)
    print()


def piped_tables(name):
    """Tables the script printed with '|' between the columns but none at the ends."""
    t = text(name)
    if t is None:
        print("(not run)\n")
        return
    for line in t.splitlines():
        if "|" in line and not line.startswith("|"):
            print("| " + line.strip() + " |")
        elif line.strip():
            print(line if line.startswith("|") else f"\n{line}\n")
    print()


def benchmark(d):
    path = os.path.join(out, d, "benchmark", "benchmark.json")
    return json.load(open(path))["methods"] if os.path.isfile(path) else None


def scene_dirs(section):
    root = os.path.join(out, section)
    if not os.path.isdir(root):
        return []
    names = [n for n in os.listdir(root) if os.path.isdir(os.path.join(root, n, "benchmark"))]
    kinds = ["orbit", "aerial", "planar", "longfocal", "tracks"]
    real = ["fountain_p11", "herzjesu_p8", "entry_p10", "temple_sparse_ring", "dino_sparse_ring"]

    def key(n):  # synthetic by kind, seed, then size; real sets in the order of docs/benchmarks.md
        kind = n.split("_")[0]
        sized = kind != "tracks" and len(n.split("_")) > 2
        where = [i for i, d in enumerate(real) if d in n] if kind == "tracks" else [0]
        return (kinds.index(kind) if kind in kinds else 9, sized, where[0] if where else 9, n)
    return sorted(names, key=key)


def scene_label(n):
    if n.startswith("tracks_"):
        return n.split("_tracks_")[-1].split("_work_shared")[0] if "_tracks_" in n else n
    return n.replace("_", ":")


def pose_rows(section, prefix):
    rows = []
    for n in scene_dirs(section):
        m = benchmark(f"{section}/{n}")
        pl, pb = m["pointless"], m["pointbased"]
        t = lambda x: x.get("cpu_seconds", float("nan"))
        label = real_name(n) or scene_label(n) + " (synthetic)"
        rows.append([prefix + label, f"{pl['rel_rot_err_deg_median']:.5f} / {pb['rel_rot_err_deg_median']:.5f}",
                     f"{pl['rel_rot_err_deg_median'] / pb['rel_rot_err_deg_median']:.3f}",
                     f"{pl['rel_rot_err_deg_max'] / pb['rel_rot_err_deg_max']:.3f}",
                     f"{pl['rel_dir_err_deg_median'] / pb['rel_dir_err_deg_median']:.3f}",
                     f"{pl['sigma_final'] / pb['sigma_final']:.3f}", f"{pl['params'] / pb['params']:.3f}",
                     f"{t(pl) / t(pb):.3f}"])
    return rows


def real_name(n):
    for d in ("fountain_p11", "herzjesu_p8", "entry_p10", "temple_sparse_ring", "dino_sparse_ring"):
        if n.startswith("tracks_") and d in n:
            return f"{d} (`pgba run` tracks)"
    return None


def pose_table():
    rows = pose_rows("pose", "") + pose_rows("pose_triplets", "paper triplets, ") + \
        pose_rows("pose_seven_view", "7-view motions, ")
    if not rows:
        print("(not run)\n")
        return
    markdown(["scene", "rel. rot. err. pointless / point-based (deg)", "ratio median", "ratio max", "dir. ratio",
              "sigma", "params", "CPU time"], rows)
    print()


def table1():
    rows = [("orbit (70 img)", "pose/orbit_1"), ("aerial (72 img)", "pose/aerial_1"),
            ("aerial (500 img)", "pose/aerial_1_500"), ("planar (60 img)", "pose/planar_1"),
            ("longfocal (93 img)", "pose/longfocal_1"),
            ("longfocal, 7-view motions", "pose_seven_view/longfocal_1"),
            ("paper triplets, orbit", "pose_triplets/orbit_1"), ("paper triplets, aerial (72)", "pose_triplets/aerial_1"),
            ("paper triplets, aerial (500)", "pose_triplets/aerial_1_500"),
            ("paper triplets, planar", "pose_triplets/planar_1"), ("paper triplets, longfocal", "pose_triplets/longfocal_1")]

    def f(m, k, fmt):
        v = m.get(k)
        return fmt % v if isinstance(v, (int, float)) else "-"
    body = []
    for label, d in rows:
        m = benchmark(d)
        if m is None:
            continue
        pl, pb, av = m["pointless"], m["pointbased"], m.get("averaging", {})
        prep = (pl["adjust_seconds"] + pl["prepare_seconds"]) / (pb["adjust_seconds"] + pb["prepare_seconds"])
        body.append([label, f(pl, "sigma_init", "%.4f"), f(pl, "sigma_final", "%.4f"), f(pb, "sigma_final", "%.4f"),
                     f(av, "sigma_final", "%.4f"), f"**{pl['sigma_final'] / pb['sigma_final']:.3f}**",
                     f"{pl['params']} / {pb['params']} (**{pl['params'] / pb['params']:.3f}**)",
                     f"{pl['adjust_seconds']:.2f} / {pb['adjust_seconds']:.2f} "
                     f"(**{pl['adjust_seconds'] / pb['adjust_seconds']:.3f}**)", f"{prep:.3f}",
                     " / ".join(f(x, "rot_err_deg_median", "%.4f") for x in (pl, pb, av)),
                     " / ".join(f(x, "loop_err_rms", "%.2f") for x in (pl, pb, av))])
    if not body:
        print("(not run)\n")
        return
    markdown(["scene", "sigma init", "sigma pointless", "sigma point-based", "sigma Aver_BA", "ratio pl/pb",
              "params pl / pb", "adjust s pl / pb", "incl. prep.", "rot err deg pl / pb / Aver",
              "loop err px pl / pb / Aver"], body)
    print()


def copied(name):
    t = text(name)
    print(t.strip() + "\n" if t else "(not run)\n")


def single_build_table(name):
    """real_self_calibration's table without its "build" column when one build ran."""
    t = text(name)
    if t is None:
        print("(not run)\n")
        return
    rows = [[c.strip() for c in l.strip().strip("|").split("|")] for l in t.splitlines() if l.startswith("|")]
    if rows and rows[0][0] == "build" and len({r[0] for r in rows[2:]}) == 1:
        rows = [r[1:] for r in rows]
    for r in rows:
        print("| " + " | ".join(r) + " |")
    print()


colmap_header = ["dataset", "method", "features s", "matching s", "SfM s", "total s", "registered", "models",
                 "rot err median", "rot err max", "centre err median", "rel. rot err median", "sigma", "focal error %"]

# (name of the table in docs/benchmarks.md, heading in tables.md, how it is printed)
tables = [
    ("pose", "Pose accuracy of the pointless BA against a point-based BA", pose_table),
    ("table1", "The paper's Table 1 on the synthetic scenes", table1),
    ("colmap", "Real images end to end, against COLMAP (calibrated)", lambda: spaced_table("colmap.txt", colmap_header)),
    ("colmap_uncal", "Real images end to end, no calibration",
     lambda: spaced_table("colmap_uncal.txt", colmap_header)),
    ("weak", "Weakly textured objects",
     lambda: spaced_table("weak.txt", ["variant", "dataset", "features/image", "adjacent pairs kept",
                                       "weak pairs confirmed", "registered", "rot err median", "rot err max", "time s"])),
    ("selfcal", "Self-calibration on synthetic scenes", lambda: copied("selfcal.txt")),
    ("realselfcal", "Self-calibration on real images", lambda: single_build_table("realselfcal.txt")),
    ("frontend", "Front-end speed", lambda: piped_tables("frontend.txt")),
    ("thousand", "A thousand photos", lambda: piped_tables("thousand.txt")),
]


def captured(fn):
    buf = io.StringIO()
    with contextlib.redirect_stdout(buf):
        fn()
    return buf.getvalue()


measured = {name: captured(fn) for name, _, fn in tables}
for name, heading, _ in tables:
    print(f"## {heading}\n")
    print(measured[name], end="")
print("## The run\n")
copied("log.txt")

if len(sys.argv) > 2:
    doc_path = sys.argv[2]
    doc = open(doc_path).read()
    for name, _, _ in tables:
        table = measured[name].strip()
        if table.startswith("(not run)"):
            continue
        block = re.compile(r"(<!-- table " + re.escape(name) + r" -->\n).*?(\n<!-- end table -->)", re.S)
        if not block.search(doc):
            print(f"warning: {doc_path} has no table '{name}'", file=sys.stderr)
            continue
        doc = block.sub(lambda m: m.group(1) + table + m.group(2), doc)
    with open(doc_path, "w") as f:
        f.write(doc)
