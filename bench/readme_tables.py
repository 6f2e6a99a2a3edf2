#!/usr/bin/env python3
"""The README's tables, in its layout, from what bench/readme_tables.sh OUT left in OUT.

Usage: bench/readme_tables.py OUT > tables.md
Each table is printed under the README heading it belongs to; a section that did not run
prints "(not run)". Numbers come from the scripts' own outputs (compare_colmap, weak_rings,
self_calibration, real_self_calibration, front_end_speed, thousand_photos) or, for the pose
and Table 1, from the benchmark.json files pose_accuracy.sh left.
"""
import json
import os
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

    def key(n):  # synthetic by kind, seed, then size; real sets in the README's order
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
print("## Measured: pose accuracy of the default (whole-track motions) against point-based\n")
pose_table()
print("## Measured: the paper's Table 1 on the synthetic scenes\n")
table1()
print("## Measured: real images end to end (calibrated)\n")
spaced_table("colmap.txt", colmap_header)
print("## Measured: real images end to end, no calibration\n")
spaced_table("colmap_uncal.txt", colmap_header)
print("## Measured: weakly textured objects\n")
spaced_table("weak.txt", ["variant", "dataset", "features/image", "adjacent pairs kept", "weak pairs confirmed",
                          "registered", "rot err median", "rot err max", "time s"])
print("## Measured: self-calibration on synthetic scenes\n")
copied("selfcal.txt")
print("## Measured: self-calibration on real images\n")
single_build_table("realselfcal.txt")
print("## Measured: front-end speed\n")
piped_tables("frontend.txt")
print("## Measured: a thousand photos\n")
piped_tables("thousand.txt")
print("## The run\n")
copied("log.txt")
