#!/usr/bin/env python3
# SPDX-License-Identifier: LGPL-2.1-or-later
# Copyright (C) 2026 by the fmpm authors
"""Write the small body files of parameters/meshes/:
disk_triangles.msh (Gmsh 2.2 ASCII, a disk of radius 0.3 about (0.5, 0.5)
in triangles, rings of 6k nodes) and sphere.stl (ASCII STL, an icosphere of
radius 0.3 about (0.5, 0.5, 0.5), 320 triangles).

    python3 contrib/utilities/make_body_meshes.py parameters/meshes

With --large-sphere N it writes instead only sphere_<T>.stl, the same
icosphere subdivided N times (T = 20 x 4^N triangles; N = 6: 81 920), for
timing the fill of a large surface (doc/bodies.md).
"""
import argparse
import math
import sys


def disk_mesh(center, radius, n_rings):
    nodes = [center]
    rings = [[0]]
    for k in range(1, n_rings + 1):
        r = radius * k / n_rings
        ring = []
        for i in range(6 * k):
            a = 2 * math.pi * i / (6 * k)
            ring.append(len(nodes))
            nodes.append((center[0] + r * math.cos(a), center[1] + r * math.sin(a)))
        rings.append(ring)
    triangles = []
    for k in range(1, n_rings + 1):
        inner, outer = rings[k - 1], rings[k]
        if len(inner) == 1:
            for j in range(len(outer)):
                triangles.append((inner[0], outer[j], outer[(j + 1) % len(outer)]))
            continue
        # Merge the two rings by angle (both start at angle 0).
        i = j = 0
        while i < len(inner) or j < len(outer):
            ai = (i + 1) / len(inner)
            aj = (j + 1) / len(outer)
            if j < len(outer) and (i == len(inner) or aj <= ai):
                triangles.append((inner[i % len(inner)], outer[j], outer[(j + 1) % len(outer)]))
                j += 1
            else:
                triangles.append((inner[i], outer[j % len(outer)], inner[(i + 1) % len(inner)]))
                i += 1
    return nodes, triangles


def write_msh(path, nodes, triangles):
    with open(path, "w") as f:
        f.write("$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n%d\n" % len(nodes))
        for n, (x, y) in enumerate(nodes):
            f.write("%d %.17g %.17g 0\n" % (n + 1, x, y))
        f.write("$EndNodes\n$Elements\n%d\n" % len(triangles))
        for e, t in enumerate(triangles):
            f.write("%d 2 2 1 1 %d %d %d\n" % (e + 1, t[0] + 1, t[1] + 1, t[2] + 1))
        f.write("$EndElements\n")


def icosphere(center, radius, n_subdivisions):
    p = (1 + 5 ** 0.5) / 2
    vertices = [(-1, p, 0), (1, p, 0), (-1, -p, 0), (1, -p, 0), (0, -1, p), (0, 1, p),
                (0, -1, -p), (0, 1, -p), (p, 0, -1), (p, 0, 1), (-p, 0, -1), (-p, 0, 1)]
    vertices = [tuple(c / math.sqrt(sum(x * x for x in v)) for c in v) for v in vertices]
    faces = [(0, 11, 5), (0, 5, 1), (0, 1, 7), (0, 7, 10), (0, 10, 11), (1, 5, 9), (5, 11, 4),
             (11, 10, 2), (10, 7, 6), (7, 1, 8), (3, 9, 4), (3, 4, 2), (3, 2, 6), (3, 6, 8),
             (3, 8, 9), (4, 9, 5), (2, 4, 11), (6, 2, 10), (8, 6, 7), (9, 8, 1)]
    for _ in range(n_subdivisions):
        middle = {}

        def mid(a, b):
            key = (min(a, b), max(a, b))
            if key not in middle:
                m = [(vertices[a][d] + vertices[b][d]) / 2 for d in range(3)]
                n = math.sqrt(sum(x * x for x in m))
                middle[key] = len(vertices)
                vertices.append(tuple(x / n for x in m))
            return middle[key]

        faces = [f for a, b, c in faces
                 for f in ((a, mid(a, b), mid(c, a)), (b, mid(b, c), mid(a, b)),
                           (c, mid(c, a), mid(b, c)), (mid(a, b), mid(b, c), mid(c, a)))]
    points = [tuple(center[d] + radius * v[d] for d in range(3)) for v in vertices]
    return points, faces


def write_stl(path, points, faces):
    with open(path, "w") as f:
        f.write("solid sphere\n")
        for face in faces:
            f.write(" facet normal 0 0 0\n  outer loop\n")
            for v in face:
                f.write("   vertex %.9g %.9g %.9g\n" % points[v])
            f.write("  endloop\n endfacet\n")
        f.write("endsolid sphere\n")


if __name__ == "__main__":
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("folder", nargs="?", default=".")
    parser.add_argument("--large-sphere", type=int, default=None)
    arguments = parser.parse_args()
    folder = arguments.folder
    if arguments.large_sphere is not None:
        points, faces = icosphere((0.5, 0.5, 0.5), 0.3, arguments.large_sphere)
        write_stl("%s/sphere_%d.stl" % (folder, len(faces)), points, faces)
        sys.exit(0)
    write_msh(folder + "/disk_triangles.msh", *disk_mesh((0.5, 0.5), 0.3, 8))
    write_stl(folder + "/sphere.stl", *icosphere((0.5, 0.5, 0.5), 0.3, 2))
