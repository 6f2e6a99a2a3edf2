#!/usr/bin/env python3
"""Per-pair view of a matching run against ground truth: where a weak image loses its pairs.

    python3 bench/pair_errors.py WS GT_MODEL [LOOP_TXT] [--all]

WS is a pgba workspace after `pgba match` / `pgba run` (WS/matching/pairs.txt,
WS/matching/two_view_geometries.txt, WS/tracks/images.txt); GT_MODEL a COLMAP text model.
Prints, per pair (only pairs <= 3 ring steps apart or verified unless --all): the ring step
(from LOOP_TXT, image names in ring order), the true relative rotation angle, the verdict,
putative matches, inliers, the rotation sd of verification and, for verified pairs, the
error of the relative rotation against the ground truth. Then a summary per ring step.
Pure Python (no numpy) so that it runs wherever bench/ does.
"""
import math
import sys

from rotation3 import angle_deg, mul, quat_to_R, transpose as tr

KEPT = ('verified', 'confirmed', 'leaf')  # verdicts of the pairs the matching stage keeps


def read_images(path):
    """name -> (id, R) from a COLMAP images.txt (pose lines only)."""
    out = {}
    lines = [l for l in open(path) if not l.startswith('#')]
    for k in range(0, len(lines), 2):
        f = lines[k].split()
        if len(f) < 10:
            continue
        out[f[9]] = (int(f[0]), quat_to_R(*map(float, f[1:5])))
    return out


def main():
    args = [a for a in sys.argv[1:] if not a.startswith('--')]
    show_all = '--all' in sys.argv
    if len(args) < 2:
        sys.exit(__doc__)
    ws, gt = args[0], args[1]
    ring = [l.strip() for l in open(args[2]) if l.strip()] if len(args) > 2 else []
    gt_images = read_images(gt + '/images.txt')
    ws_images = read_images(ws + '/tracks/images.txt')
    name_of = {i: n for n, (i, _) in ws_images.items()}
    geo = {}
    for l in open(ws + '/matching/two_view_geometries.txt'):
        if l.startswith('#') or not l.strip():
            continue
        f = l.split()
        geo[(name_of[int(f[0])], name_of[int(f[1])])] = quat_to_R(*map(float, f[2:6]))

    def step(a, b):
        if a not in ring or b not in ring:
            return -1
        d = abs(ring.index(a) - ring.index(b))
        return min(d, len(ring) - d)

    rows = []
    for l in open(ws + '/matching/pairs.txt'):
        if l.startswith('#') or not l.strip():
            continue
        n1, n2, put, inl, sd, tri, verdict = l.split()
        R1, R2 = gt_images[n1][1], gt_images[n2][1]
        R_gt = mul(R2, tr(R1))
        err = ''
        if (n1, n2) in geo:
            err = '%.3f' % angle_deg(mul(geo[(n1, n2)], tr(R_gt)))
        rows.append((step(n1, n2), n1, n2, angle_deg(R_gt), verdict, int(put), int(inl), sd, err))
    rows.sort()
    print('%-4s %-16s %-16s %7s %-18s %6s %6s %9s %8s' %
          ('step', 'image1', 'image2', 'gt_deg', 'verdict', 'put', 'inl', 'rot_sd', 'rot_err'))
    for r in rows:
        if show_all or r[0] <= 3 or r[4] in KEPT:
            print('%-4d %-16s %-16s %7.1f %-18s %6d %6d %9s %8s' % r)
    print('\nstep  pairs  kept  median_putative  median_inliers  kept_rot_err_median  kept_rot_err_max')
    for s in sorted(set(r[0] for r in rows)):
        sel = [r for r in rows if r[0] == s]
        ver = [r for r in sel if r[4] in KEPT]
        put = sorted(r[5] for r in sel)
        inl = sorted(r[6] for r in sel)
        errs = sorted(float(r[8]) for r in ver if r[8])
        med = '%.3f' % errs[len(errs) // 2] if errs else '-'
        mx = '%.3f' % errs[-1] if errs else '-'
        print('%4d  %5d  %4d  %15d  %14d  %19s  %16s' % (s, len(sel), len(ver), put[len(put) // 2], inl[len(inl) // 2],
                                                    med, mx))


if __name__ == '__main__':
    main()
