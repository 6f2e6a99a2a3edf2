"""3 x 3 rotations as nested lists for the bench scripts (pure Python: no numpy needed)."""
import math


def quat_to_R(w, x, y, z):
    """Rotation matrix of the quaternion (w, x, y, z), normalised first (COLMAP's convention)."""
    n = math.sqrt(w * w + x * x + y * y + z * z)
    w, x, y, z = w / n, x / n, y / n, z / n
    return [[1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
            [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
            [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)]]


def mul(A, B):
    return [[sum(A[i][k] * B[k][j] for k in range(3)) for j in range(3)] for i in range(3)]


def transpose(A):
    return [[A[j][i] for j in range(3)] for i in range(3)]


def apply(A, v):
    return [sum(A[i][k] * v[k] for k in range(3)) for i in range(3)]


def angle_deg(R):
    """The rotation angle of R, degrees."""
    c = (R[0][0] + R[1][1] + R[2][2] - 1) / 2
    return math.degrees(math.acos(max(-1.0, min(1.0, c))))
