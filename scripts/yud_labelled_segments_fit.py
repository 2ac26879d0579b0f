#!/usr/bin/env python3
"""How close York Urban's labelled vanishing directions are to each family's own least-squares
point of the dataset's hand-labelled segments, with the true K (no detection at all).

    python3 scripts/yud_labelled_segments_fit.py ../shared/data/yud-train

For every label file (`K`, `segments_xyxy`, `segment_vp_index0`, `vp_dirs_camera_yup`,
`most_vertical_vp_index`) and each of its three families: the direction `v` minimising
sum_i w_i (l_i . v)^2 over the family's segments, `l_i` the segment's line through `K^-1` scaled to
a unit normal in the normalised image, `w_i` its length in pixels (the classical algebraic
least-squares point, not held orthogonal to the other families); a family with fewer than two
labelled segments has no point and counts as a miss (infinite error). Prints the sign-free angle to
the labelled direction as `vpmap eval-detect` scores it: the median, p90 and largest error, the
vertical's and the horizontals' medians, and AA@3/5/10 (the mean of max(0, 1 - error / L)).
Standard library only.
"""

import glob
import json
import math
import os
import sys


def mat_vec(m, v):
    return [sum(m[i][j] * v[j] for j in range(3)) for i in range(3)]


def inverse3(m):
    (a, b, c), (d, e, f), (g, h, i) = m
    cof = [
        [e * i - f * h, -(d * i - f * g), d * h - e * g],
        [-(b * i - c * h), a * i - c * g, -(a * h - b * g)],
        [b * f - c * e, -(a * f - c * d), a * e - b * d],
    ]
    det = a * cof[0][0] + b * cof[0][1] + c * cof[0][2]
    return [[cof[j][i] / det for j in range(3)] for i in range(3)]


def cross(a, b):
    return [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]


def unit(v):
    n = math.sqrt(sum(x * x for x in v))
    return [x / n for x in v]


def smallest_eigenvector(m):
    """Of a symmetric positive semi-definite 3x3 matrix, by inverse iteration."""
    scale = max(abs(x) for row in m for x in row) or 1.0
    shifted = [[m[i][j] + (1e-12 * scale if i == j else 0.0) for j in range(3)] for i in range(3)]
    inv = inverse3(shifted)
    v = unit([1.0, 0.7, 0.3])
    for _ in range(100):
        v = unit(mat_vec(inv, v))
    return v


def family_point(k_inv, segments):
    m = [[0.0] * 3 for _ in range(3)]
    for x1, y1, x2, y2 in segments:
        line = cross(mat_vec(k_inv, [x1, y1, 1.0]), mat_vec(k_inv, [x2, y2, 1.0]))
        n = math.hypot(line[0], line[1])
        if n == 0.0:
            continue
        line = [x / n for x in line]
        w = math.hypot(x2 - x1, y2 - y1)
        for r in range(3):
            for c in range(3):
                m[r][c] += w * line[r] * line[c]
    return smallest_eigenvector(m)


def median(values):
    s = sorted(values)
    n = len(s)
    return s[n // 2] if n % 2 else 0.5 * (s[n // 2 - 1] + s[n // 2])


def main(folder):
    errors, vertical, horizontal = [], [], []
    for path in sorted(glob.glob(os.path.join(folder, "*.json"))):
        with open(path) as f:
            label = json.load(f)
        k_inv = inverse3(label["K"])
        segments = label["segments_xyxy"]
        family = label["segment_vp_index0"]
        for k, labelled in enumerate(label["vp_dirs_camera_yup"]):
            mine = [s for s, j in zip(segments, family) if j == k]
            if len(mine) < 2:
                errors.append(math.inf)
                (vertical if k == label["most_vertical_vp_index"] else horizontal).append(math.inf)
                continue
            v = family_point(k_inv, mine)
            # y up to y down, as the segments' pixels.
            truth = unit([labelled[0], -labelled[1], labelled[2]])
            c = abs(sum(a * b for a, b in zip(v, truth)))
            error = math.degrees(math.atan2(math.sqrt(max(0.0, 1.0 - c * c)), c))
            errors.append(error)
            (vertical if k == label["most_vertical_vp_index"] else horizontal).append(error)
    if not errors:
        sys.exit(f"no label files in {folder}")
    s = sorted(errors)
    aa = [100.0 * sum(max(0.0, 1.0 - e / lim) for e in errors) / len(errors) for lim in (3, 5, 10)]
    missed = sum(1 for e in errors if math.isinf(e))
    print(
        f"{len(errors)} labelled directions in {folder}; {missed} with fewer than two labelled "
        "segments (misses)"
    )
    print(
        f"error of each family's own least-squares point of the labelled segments (deg): "
        f"median {median(errors):.2f}, p90 {s[int(0.9 * (len(s) - 1))]:.2f}, largest finite {max(e for e in s if math.isfinite(e)):.1f}; "
        f"vertical median {median(vertical):.2f}, horizontal median {median(horizontal):.2f}"
    )
    print("AA@3/5/10: {:.1f} / {:.1f} / {:.1f} %".format(*aa))


if __name__ == "__main__":
    main(sys.argv[1] if len(sys.argv) > 1 else "../shared/data/yud-train")
