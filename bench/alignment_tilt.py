#!/usr/bin/env python3
"""How much of a model's rotation error against ground truth is its alignment's.

    python3 bench/alignment_tilt.py MODEL GT_MODEL

MODEL and GT_MODEL are COLMAP text models (images.txt is read). Prints each common image's
rotation error (degrees) under
  - the similarity fitted to the camera centres (what `pgba evaluate` and report.json's
    rot_err_deg use, without its outlier rounds),
  - the rotation that best fits the camera rotations themselves (the chordal mean of
    R_gt^T R_est): the model's rotations up to one common rotation,
  - the centre similarity fitted without each image in turn,
with each image's centre error relative to the ground truth's largest centre distance. A
model whose errors drop from the first row to the second is internally right and tilted by
its alignment; the leave-one-out rows name the centre that tilts it.
Pure Python (no numpy) so that it runs wherever bench/ does.
"""
import math
import sys

from rotation3 import angle_deg, apply, mul, quat_to_R, transpose as T


def read_images(folder):
    """name -> (R, C) from a COLMAP images.txt (world -> camera R, centre C)."""
    poses = {}
    with open(folder.rstrip('/') + '/images.txt') as f:
        lines = [l for l in f if not l.startswith('#')]
    i = 0
    while i < len(lines):
        fields = lines[i].split()
        if len(fields) >= 10:
            R = quat_to_R(*map(float, fields[1:5]))
            t = list(map(float, fields[5:8]))
            poses[fields[9]] = (R, [-c for c in apply(T(R), t)])
            i += 2
        else:
            i += 1
    return poses


def best_rotation(S):
    """Horn's quaternion method: S[i][j] = sum of src_i * dst_j over the correspondences;
    the rotation A with dst ~ A src in least squares."""
    (xx, xy, xz), (yx, yy, yz), (zx, zy, zz) = S
    N = [[xx + yy + zz, yz - zy, zx - xz, xy - yx],
         [yz - zy, xx - yy - zz, xy + yx, zx + xz],
         [zx - xz, xy + yx, -xx + yy - zz, yz + zy],
         [xy - yx, zx + xz, yz + zy, -xx - yy + zz]]
    shift = sum(abs(v) for row in N for v in row)
    M = [[N[i][j] + (shift if i == j else 0) for j in range(4)] for i in range(4)]
    q = [1.0, 0.1, 0.01, 0.001]
    for _ in range(5000):  # power iteration on the shifted matrix: its largest eigenvector
        w = [sum(M[i][j] * q[j] for j in range(4)) for i in range(4)]
        n = math.sqrt(sum(v * v for v in w))
        q = [v / n for v in w]
    return quat_to_R(*q)


def centre_similarity(est, gt, names):
    """(s, A, t) with gt C ~ s A est C + t over `names` (Umeyama through Horn)."""
    ms = [sum(est[n][1][i] for n in names) / len(names) for i in range(3)]
    md = [sum(gt[n][1][i] for n in names) / len(names) for i in range(3)]
    S = [[sum((est[n][1][i] - ms[i]) * (gt[n][1][j] - md[j]) for n in names) for j in range(3)] for i in range(3)]
    A = best_rotation(S)
    num = sum(sum((gt[n][1][i] - md[i]) * apply(A, [est[n][1][k] - ms[k] for k in range(3)])[i] for i in range(3))
              for n in names)
    den = sum(sum((est[n][1][k] - ms[k]) ** 2 for k in range(3)) for n in names)
    s = num / den
    sAm = apply(A, ms)
    return s, A, [md[i] - s * sAm[i] for i in range(3)]


def median(values):
    v = sorted(values)
    return v[len(v) // 2] if len(v) % 2 else (v[len(v) // 2 - 1] + v[len(v) // 2]) / 2


def main():
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    est, gt = read_images(sys.argv[1]), read_images(sys.argv[2])
    names = sorted(set(est) & set(gt))
    if len(names) < 3:
        sys.exit('fewer than 3 common images')
    extent = max(math.dist(a[1], b[1]) for a in gt.values() for b in gt.values())

    def row(label, A, sim=None):
        errors = [angle_deg(mul(mul(est[n][0], T(A)), T(gt[n][0]))) for n in names]
        cells = ' '.join('%s %.2f' % (n, e) for n, e in zip(names, errors))
        line = '%-24s median %.3f max %.3f | %s' % (label, median(errors), max(errors), cells)
        if sim:
            s, R, t = sim
            centre = [math.dist([s * v + w for v, w in zip(apply(R, est[n][1]), t)], gt[n][1]) / extent for n in names]
            line += ' | centre ' + ' '.join('%.4f' % c for c in centre)
        print(line)

    sim = centre_similarity(est, gt, names)
    row('centre similarity', sim[1], sim)
    S = [[0.0] * 3 for _ in range(3)]
    for n in names:  # src: the basis vectors, dst: the columns of R_gt^T R_est
        M = mul(T(gt[n][0]), est[n][0])
        for i in range(3):
            for j in range(3):
                S[i][j] += M[j][i]
    row('rotations alone', best_rotation(S))
    for left_out in names:
        sim = centre_similarity(est, gt, [n for n in names if n != left_out])
        row('centres without ' + left_out, sim[1], sim)


if __name__ == '__main__':
    main()
