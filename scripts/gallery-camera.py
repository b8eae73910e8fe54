#!/usr/bin/env python3
"""Prints a `freeform render --camera` value that frames what an edit moved: the vertices of
REST.off that differ in the other OFF files, seen from the front (+z for y up, -y for z up).
    scripts/gallery-camera.py UP REST.off DEFORMED.off [MORE.off ...]"""
import sys


def read_off(path: str) -> list[tuple[float, float, float]]:
    with open(path, encoding="utf-8") as f:
        tokens = f.read().split()
    if tokens[0] not in ("OFF", "COFF"):
        raise SystemExit(f"{path}: not an OFF file")
    n = int(tokens[1])
    return [(float(tokens[4 + 3 * i]), float(tokens[5 + 3 * i]), float(tokens[6 + 3 * i])) for i in range(n)]


def main() -> int:
    if len(sys.argv) < 4:
        print(__doc__, file=sys.stderr)
        return 2
    up, rest = sys.argv[1], read_off(sys.argv[2])
    points = []
    for path in sys.argv[3:]:
        other = read_off(path)
        for a, b in zip(rest, other):
            if max(abs(x - y) for x, y in zip(a, b)) > 1e-9:
                points += [a, b]
    if not points:
        points = rest
    lo = [min(p[i] for p in points) for i in range(3)]
    hi = [max(p[i] for p in points) for i in range(3)]
    c = [(lo[i] + hi[i]) / 2 for i in range(3)]
    size = max(hi[i] - lo[i] for i in range(3))
    if up == "y":
        eye, up_vec = (c[0], c[1], c[2] + 2.2 * size), "0,1,0"
    else:
        eye, up_vec = (c[0], c[1] - 2.2 * size, c[2]), "0,0,1"
    print(f"eye={eye[0]:.6g},{eye[1]:.6g},{eye[2]:.6g};target={c[0]:.6g},{c[1]:.6g},{c[2]:.6g};up={up_vec};fov=35")
    return 0


if __name__ == "__main__":
    sys.exit(main())
