#!/usr/bin/env python3
"""Where the Merton dataset's own 3D points and lines put the two walls, and so the corner.

The example scene's reference values (corner at x -0.3, angle 90 degrees) come from the
dataset's README. This script measures them from the triangulated points (3D/p3d) and lines
(3D/l3d) in the scene's Z-up frame, with four estimators, so that a reader can see how far
the reference itself is known. Standard library only:

    python3 docs/examples/merton/reference_fits.py [DATA_DIR]

DATA_DIR defaults to ../shared/data/merton_college_1 beside the repository.
"""
import math
import pathlib
import sys

# Wall A lies near the plane y = 0 (facing +y, x from 0 to 9.3), wall B near x = -0.3 (facing
# +x, y from 0 to 8.4). Points below the eaves and within these bands count as the wall's.
WALL_A = dict(u=0, v=1, u_range=(0.5, 9.5), v_range=(-1.0, 0.6))
WALL_B = dict(u=1, v=0, u_range=(0.5, 9.0), v_range=(-1.5, 0.6))
BELOW_EAVES = (0.3, 4.6)


def read_rows(path):
    return [tuple(map(float, line.split())) for line in open(path) if line.strip() and not line.startswith("#")]


def least_squares(u, v, w=None):
    """v = a + b u, weighted."""
    w = w or [1.0] * len(u)
    total = sum(w)
    mu = sum(wi * x for wi, x in zip(w, u)) / total
    mv = sum(wi * y for wi, y in zip(w, v)) / total
    b = sum(wi * (x - mu) * (y - mv) for wi, x, y in zip(w, u, v)) / sum(wi * (x - mu) ** 2 for wi, x in zip(w, u))
    return mv - b * mu, b


def huber(u, v, c=0.05, rounds=30):
    """Least squares with Huber weights (residuals beyond c metres count linearly): the lamp,
    the drainpipes and stray matches do not tilt the fit."""
    a, b = least_squares(u, v)
    for _ in range(rounds):
        w = [1.0 if abs(y - a - b * x) <= c else c / abs(y - a - b * x) for x, y in zip(u, v)]
        a, b = least_squares(u, v, w)
    return a, b


def on_wall(p, wall):
    return (wall["u_range"][0] < p[wall["u"]] < wall["u_range"][1]
            and wall["v_range"][0] < p[wall["v"]] < wall["v_range"][1]
            and BELOW_EAVES[0] < p[2] < BELOW_EAVES[1])


def front_quarter(points, wall):
    """Per metre along the wall, the quarter of its points nearest the cameras: the stone face,
    not the recessed windows and doors behind it."""
    u, v = [], []
    for k in range(10):
        band = sorted((p for p in points if k <= p[wall["u"]] < k + 1), key=lambda p: p[wall["v"]])
        if len(band) >= 3:
            front = band[-max(1, len(band) // 4):]
            u += [p[wall["u"]] for p in front]
            v += [p[wall["v"]] for p in front]
    return u, v


def line_midpoints(lines, wall):
    """Midpoints of the lines on the wall that run along it or upright (the reconstruction
    aligned every line with a vanishing direction, so only their positions carry news)."""
    u, v = [], []
    for x0, y0, z0, x1, y1, z1 in lines:
        p0, p1 = (x0, y0, z0), (x1, y1, z1)
        mid = tuple((a + b) / 2 for a, b in zip(p0, p1))
        if not on_wall(mid, wall):
            continue
        if abs(p1[wall["u"]] - p0[wall["u"]]) < 0.5 and abs(p1[2] - p0[2]) < 0.5:
            continue
        u.append(mid[wall["u"]])
        v.append(mid[wall["v"]])
    return u, v


def corner(fit_a, fit_b):
    """Wall A: y = aA + bA x; wall B: x = aB + bB y. Their intersection and the angle between
    the walls (90 degrees when both are axis-aligned)."""
    (a_a, b_a), (a_b, b_b) = fit_a, fit_b
    y = (a_a + b_a * a_b) / (1.0 - b_a * b_b)
    x = a_b + b_b * y
    angle = 90.0 - math.degrees(math.atan(b_a)) - math.degrees(math.atan(b_b))
    return x, y, angle


def main():
    data = pathlib.Path(sys.argv[1]) if len(sys.argv) > 1 else (
        pathlib.Path(__file__).resolve().parents[3] / ".." / "shared" / "data" / "merton_college_1")
    for name in ("points3d_zup.txt", "lines3d_zup.txt"):
        if not (data / name).is_file():
            print(f"reference_fits.py: {data / name}: not found (give the dataset's folder as the argument)",
                  file=sys.stderr)
            sys.exit(2)
    points = read_rows(data / "points3d_zup.txt")
    lines = read_rows(data / "lines3d_zup.txt")
    wall_a = [p for p in points if on_wall(p, WALL_A)]
    wall_b = [p for p in points if on_wall(p, WALL_B)]

    def split(ps, wall):
        return [p[wall["u"]] for p in ps], [p[wall["v"]] for p in ps]

    estimates = [
        ("points, least squares", least_squares(*split(wall_a, WALL_A)), least_squares(*split(wall_b, WALL_B))),
        ("points, Huber (5 cm)", huber(*split(wall_a, WALL_A)), huber(*split(wall_b, WALL_B))),
        ("points, front quarter", huber(*front_quarter(wall_a, WALL_A)), huber(*front_quarter(wall_b, WALL_B))),
        ("line midpoints, Huber", huber(*line_midpoints(lines, WALL_A)), huber(*line_midpoints(lines, WALL_B))),
    ]
    print(f"{len(wall_a)} points on wall A, {len(wall_b)} on wall B")
    print("| estimate | wall A: y = a + b x | wall B: x = a + b y | corner (x, y) | angle |")
    print("|---|---|---|---|---|")
    for name, fit_a, fit_b in estimates:
        x, y, angle = corner(fit_a, fit_b)
        print(f"| {name} | {fit_a[0]:+.3f} {fit_a[1]:+.4f} x | {fit_b[0]:+.3f} {fit_b[1]:+.4f} y "
              f"| ({x:.2f}, {y:.2f}) | {angle:.1f}° |")
    # How deep the relief is: per metre of wall B, the spread of its points across the wall.
    print("\nwall B, per metre along it: points, median x, nearest the cameras, farthest")
    for k in range(9):
        xs = sorted(p[0] for p in wall_b if k <= p[1] < k + 1)
        if xs:
            print(f"  y {k}-{k + 1}: {len(xs):3d}  {xs[len(xs) // 2]:+.2f}  {xs[-1]:+.2f}  {xs[0]:+.2f}")


if __name__ == "__main__":
    main()
