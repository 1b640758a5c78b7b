#!/usr/bin/env python3
"""Writes the labelCloud example files of box_formats_reference_test.cpp from three known boxes,
by labelCloud's rules (no labelCloud code): centroid_abs with degrees in [0, 360), centroid_rel
with radians in (-pi, pi], and vertices in labelCloud's corner order rotated by R = Rz Ry Rx."""
import json
import math

BOXES = [  # name, centroid x y z, length width height, rotations x y z in degrees [0, 360)
    ("chair", (1.25, -0.5, 0.45), (0.6, 0.55, 0.9), (0.0, 0.0, 330.0)),
    ("table", (0.0, 1.5, 0.375), (1.6, 0.8, 0.75), (355.0, 10.0, 90.0)),
    ("lamp", (-1.0, -1.0, 1.2), (0.3, 0.25, 0.5), (12.5, 0.0, 47.25)),
]
# labelCloud's vertex order: local signs of (length, width, height)
SIGNS = [(-1, -1, -1), (-1, 1, -1), (1, 1, -1), (1, -1, -1), (-1, -1, 1), (-1, 1, 1), (1, 1, 1), (1, -1, 1)]


def rotate_x_then_y_then_z(v, deg):
    x, y, z = v
    a, b, c = (math.radians(d) for d in deg)
    y, z = y * math.cos(a) - z * math.sin(a), y * math.sin(a) + z * math.cos(a)
    x, z = x * math.cos(b) + z * math.sin(b), -x * math.sin(b) + z * math.cos(b)
    x, y = x * math.cos(c) - y * math.sin(c), x * math.sin(c) + y * math.cos(c)
    return (x, y, z)


def relative(deg):
    rad = math.radians(deg)
    return rad - 2 * math.pi if rad > math.pi else rad


def file(objects):
    return {"folder": "pointclouds", "filename": "office.pcd", "path": "pointclouds/office.pcd", "objects": objects}


def centroid(radians):
    return file([{"name": n, "centroid": dict(zip("xyz", c)), "dimensions": dict(zip(("length", "width", "height"), d)),
                  "rotations": dict(zip("xyz", [relative(a) for a in r] if radians else r))} for n, c, d, r in BOXES])


def vertices():
    objects = []
    for n, c, d, r in BOXES:
        corners = []
        for s in SIGNS:
            local = tuple(si * di / 2 for si, di in zip(s, d))
            corners.append([ci + vi for ci, vi in zip(c, rotate_x_then_y_then_z(local, r))])
        objects.append({"name": n, "vertices": corners})
    return file(objects)


for name, content in [("labelcloud_centroid_abs.json", centroid(False)),
                      ("labelcloud_centroid_rel.json", centroid(True)),
                      ("labelcloud_vertices.json", vertices())]:
    with open(name, "w") as f:
        json.dump(content, f, indent=2)
        f.write("\n")
