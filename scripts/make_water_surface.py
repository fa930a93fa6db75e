#!/usr/bin/env python3
"""Writes configs/meshes/water_ripples.obj: a block of water with a rippled top, for
configs/water_caustics.toml (issue 59).

The block spans x, z in [-HALF, HALF] and y in [BOTTOM, LEVEL + ripple]. The top is an N x N grid
whose heights are a sum of three sine waves (amplitude and wavelength chosen so the crests focus
refracted light about 0.5-1 below the surface, f ~ n / ((n - 1) A k^2)); four side strips and a
fan over the bottom close it. Every triangle is wound outwards (the dielectric mesh must be
closed and consistently oriented, docs/caustics.md). Deterministic: no random numbers.

Usage: python3 scripts/make_water_surface.py [OUT.obj]
"""
import math
import sys

N = 48            # grid cells per side on the top surface
HALF = 1.5        # half extent in x and z
LEVEL = 1.0       # mean height of the surface
BOTTOM = -0.02    # the block's bottom, just below the floor quad at y = 0
# (amplitude, wavelength, direction in degrees, phase)
WAVES = [(0.020, 0.55, 20.0, 0.0), (0.015, 0.43, 110.0, 1.3), (0.010, 0.31, 65.0, 2.1)]


def height(x, z):
    h = LEVEL
    for amplitude, wavelength, degrees, phase in WAVES:
        a = math.radians(degrees)
        k = 2.0 * math.pi / wavelength
        h += amplitude * math.sin(k * (x * math.cos(a) + z * math.sin(a)) + phase)
    return h


def main():
    out = sys.argv[1] if len(sys.argv) > 1 else "configs/meshes/water_ripples.obj"
    vertices = []
    faces = []

    def coord(i):
        return -HALF + 2.0 * HALF * i / N

    top = {}
    for i in range(N + 1):
        for j in range(N + 1):
            x, z = coord(i), coord(j)
            vertices.append((x, height(x, z), z))
            top[(i, j)] = len(vertices)
    # Top: normal +y. With x along i and z along j, (i,j) -> (i,j+1) -> (i+1,j) turns from +z
    # to +x, whose cross product (z x x) is +y.
    for i in range(N):
        for j in range(N):
            a, b, c, d = top[(i, j)], top[(i + 1, j)], top[(i + 1, j + 1)], top[(i, j + 1)]
            faces.append((a, d, b))
            faces.append((b, d, c))
    # The boundary of the top grid as one loop; its orientation (the sign of its area) decides the
    # winding of the sides and the bottom fan.
    loop = [(i, 0) for i in range(N)] + [(N, j) for j in range(N)] + \
           [(i, N) for i in range(N, 0, -1)] + [(0, j) for j in range(N, 0, -1)]
    bottom = {}
    for key in loop:
        x, _, z = vertices[top[key] - 1]
        vertices.append((x, BOTTOM, z))
        bottom[key] = len(vertices)
    vertices.append((0.0, BOTTOM, 0.0))
    centre = len(vertices)
    # Signed area of the loop in the (z, x) plane decides which way the sides and bottom wind.
    area = 0.0
    for n, key in enumerate(loop):
        x0, _, z0 = vertices[top[key] - 1]
        x1, _, z1 = vertices[top[loop[(n + 1) % len(loop)]] - 1]
        area += z0 * x1 - z1 * x0
    for n, key in enumerate(loop):
        nxt = loop[(n + 1) % len(loop)]
        t0, t1, b0, b1 = top[key], top[nxt], bottom[key], bottom[nxt]
        if area > 0:  # loop turns from +z to +x: counter-clockwise about +y
            faces.append((t0, b0, t1))
            faces.append((t1, b0, b1))
            faces.append((b0, centre, b1))
        else:
            faces.append((t0, t1, b0))
            faces.append((t1, b1, b0))
            faces.append((b0, b1, centre))
    check_closed(faces)
    check_outward(vertices, faces)
    with open(out, "w") as f:
        f.write("# A block of water with a rippled top for configs/water_caustics.toml; written by\n")
        f.write("# scripts/make_water_surface.py (closed, every face wound outwards).\n")
        for v in vertices:
            f.write("v %.6f %.6f %.6f\n" % v)
        for t in faces:
            f.write("f %d %d %d\n" % t)
    print("%s: %d vertices, %d triangles" % (out, len(vertices), len(faces)))


def check_closed(faces):
    edges = {}
    for t in faces:
        for e in ((t[0], t[1]), (t[1], t[2]), (t[2], t[0])):
            edges[e] = edges.get(e, 0) + 1
    for (a, b), count in edges.items():
        if count != 1 or edges.get((b, a), 0) != 1:
            raise SystemExit("mesh not closed or not consistently wound at edge %d-%d" % (a, b))


def check_outward(vertices, faces):
    volume = 0.0
    for a, b, c in faces:
        p, q, r = vertices[a - 1], vertices[b - 1], vertices[c - 1]
        volume += (p[0] * (q[1] * r[2] - q[2] * r[1]) - p[1] * (q[0] * r[2] - q[2] * r[0])
                   + p[2] * (q[0] * r[1] - q[1] * r[0])) / 6.0
    if volume <= 0.0:
        raise SystemExit("mesh wound inwards (signed volume %g)" % volume)


if __name__ == "__main__":
    main()
