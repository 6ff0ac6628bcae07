#!/usr/bin/python3
"""Writes the small glTF casters of the stability suite into data/stability/ (standard library only).

    make-stability-meshes.py [OUT_DIR]     (default: data/stability/ beside this script's folder)

Every file is a .gltf with its buffer embedded as a base64 data URI: POSITION (float VEC3, with
min/max) and uint32 indices, one mesh, one node, no transform. Output is deterministic, so the
committed files can be regenerated and diffed.

Sliver / degenerate casters (slivers-degenerate.json):
  sliver-slab.gltf   a closed 1.0 x 0.08 x 0.6 m slab written the way exporters write flat-shaded
                     boxes (every face group has its own vertex copies, some copies off by 0.3 um,
                     under the weld tolerance). Its top and bottom are fans from the face centre:
                     along the front edge 21 vertices 10 um apart give needle triangles (10 um base,
                     0.3 m long) and 10 um x 0.08 m side strips; along the back edge three "cap"
                     slivers (a vertex 10 um, 1 um and ~0.1 um inside the straight edge, so the
                     triangle has an angle near 180 degrees). Extra triangles that must vanish:
                     one with three exactly collinear corners (zero area, on an edge that already
                     has two triangles), one repeating an index, one with a zero-length edge
                     (two indices, same position), one with a 0.4 um edge (welded away).
  sliver-strip.gltf  an open 0.6 x 0.5 m single-layer plate as TRIANGLE_STRIP: 6 mm x 0.5 m
                     quads split on the diagonal (aspect ~83), two strips joined by the usual
                     repeated indices (four index-degenerate triangles).

Open and non-manifold casters (open-nonmanifold.json):
  open-box.gltf      a 0.6 x 0.4 x 0.6 m box without its top and its front face, one layer of
                     triangles, outward winding: boundary edges along the whole rim.
  fan.gltf           a single-sided 12-triangle disc (r = 0.3 m) as TRIANGLE_FAN, wound to face
                     down (away from the light): every rim edge a boundary edge.
  fins.gltf          a "book": four 0.6 x 0.3 m fins on one spine at 0, 55, 115 and 165 degrees
                     about it; the spine edge is shared by four triangles.
  tee.gltf           a 0.7 x 0.5 m plate with a 0.25 m fin standing on its centre line (a T):
                     the centre-line edges are shared by three triangles.
  cubes-edge.gltf    two closed 0.3 m cubes touching along one edge (that edge: four triangles;
                     its two end vertices join two closed fans).
"""
import base64
import json
import math
import os
import struct
import sys


def f32(x):
    """x rounded to float32, as it will be stored."""
    return struct.unpack("<f", struct.pack("<f", x))[0]


class Primitive:
    def __init__(self, mode=4):
        self.mode = mode  # 4 TRIANGLES, 5 TRIANGLE_STRIP, 6 TRIANGLE_FAN
        self.positions = []
        self.indices = []

    def vertex(self, p):
        self.positions.append(tuple(f32(c) for c in p))
        return len(self.positions) - 1

    def tri(self, a, b, c):
        self.indices += [a, b, c]


def write_gltf(path, primitives, name):
    blob = bytearray()
    views, accessors, prims = [], [], []
    for prim in primitives:
        pos_bytes = b"".join(struct.pack("<3f", *p) for p in prim.positions)
        idx_bytes = struct.pack("<%dI" % len(prim.indices), *prim.indices)
        lo = [min(p[k] for p in prim.positions) for k in range(3)]
        hi = [max(p[k] for p in prim.positions) for k in range(3)]
        views.append({"buffer": 0, "byteOffset": len(blob), "byteLength": len(pos_bytes),
                      "target": 34962})
        blob += pos_bytes
        accessors.append({"bufferView": len(views) - 1, "componentType": 5126,
                          "count": len(prim.positions), "type": "VEC3", "min": lo, "max": hi})
        views.append({"buffer": 0, "byteOffset": len(blob), "byteLength": len(idx_bytes),
                      "target": 34963})
        blob += idx_bytes
        accessors.append({"bufferView": len(views) - 1, "componentType": 5125,
                          "count": len(prim.indices), "type": "SCALAR"})
        prims.append({"attributes": {"POSITION": len(accessors) - 2},
                      "indices": len(accessors) - 1, "mode": prim.mode})
    doc = {
        "asset": {"version": "2.0", "generator": "penumbra scripts/make-stability-meshes.py"},
        "scene": 0,
        "scenes": [{"nodes": [0]}],
        "nodes": [{"name": name, "mesh": 0}],
        "meshes": [{"name": name, "primitives": prims}],
        "accessors": accessors,
        "bufferViews": views,
        "buffers": [{"byteLength": len(blob),
                     "uri": "data:application/octet-stream;base64," +
                            base64.b64encode(bytes(blob)).decode("ascii")}],
    }
    with open(path, "w") as f:
        json.dump(doc, f, indent=1)
        f.write("\n")


# --- small vector helpers -------------------------------------------------------------------------

def sub(a, b):
    return tuple(x - y for x, y in zip(a, b))


def cross(a, b):
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


def dot(a, b):
    return sum(x * y for x, y in zip(a, b))


def normal(prim, t):
    a, b, c = (prim.positions[i] for i in prim.indices[3 * t:3 * t + 3])
    return cross(sub(b, a), sub(c, a))


def check_outward(prim, inside, skip=()):
    """Every triangle (but those listed) has positive area and faces away from `inside`."""
    for t in range(len(prim.indices) // 3):
        if t in skip:
            continue
        a = prim.positions[prim.indices[3 * t]]
        n = normal(prim, t)
        assert dot(n, n) > 0.0, "triangle %d has no area" % t
        assert dot(n, sub(a, inside)) > 0.0, "triangle %d faces inwards" % t


def quad(prim, a, b, c, d):
    """Two triangles a b c, a c d (counter-clockwise seen from the front)."""
    prim.tri(a, b, c)
    prim.tri(a, c, d)


# --- slivers and degenerate triangles -------------------------------------------------------------

def sliver_slab():
    hx, hy, hz = 0.5, 0.04, 0.3
    # Boundary of the top/bottom face, ordered so that the top fan triangles (centre, B[i],
    # B[i+1]) face +y (check_outward below verifies every face).
    front = [-0.5, -0.25] + [k * 1e-5 for k in range(-10, 11)] + [0.25]
    boundary = [(x, hz) for x in front]                            # front edge, x increasing
    boundary += [(hx, hz), (hx, 0.0)]                                # right edge
    boundary += [(hx, -hz), (0.25, -hz), (0.0, -hz), (-0.25, -hz)]   # back edge, x decreasing
    boundary += [(-hx, -hz), (-hx, -0.1), (-hx, 0.0), (-hx, 0.1)]   # left edge (collinear run)
    n = len(boundary)
    # Cap slivers on back-edge segments: (segment start x, height of the inner vertex).
    caps = {0.5: 1e-5, 0.25: 1e-6, 0.0: 1e-7}

    prim = Primitive()
    # Top face (normal +y): fan from its centre.
    c = prim.vertex((0.0, hy, 0.0))
    top = [prim.vertex((x, hy, z)) for x, z in boundary]
    for i in range(n):
        a, b = top[i], top[(i + 1) % n]
        (ax, az), (bx, bz) = boundary[i], boundary[(i + 1) % n]
        if az == -hz and bz == -hz and ax in caps:
            m = prim.vertex(((ax + bx) / 2, hy, -hz + caps[ax]))
            prim.tri(c, a, m)
            prim.tri(c, m, b)
            prim.tri(a, b, m)
        else:
            prim.tri(c, a, b)

    # Bottom face (normal -y): its own vertex copies, fan the other way round.
    c = prim.vertex((0.0, -hy, 0.0))
    bottom = [prim.vertex((x, -hy, z)) for x, z in boundary]
    for i in range(n):
        prim.tri(c, bottom[(i + 1) % n], bottom[i])

    # Sides: one quad per boundary segment, its own four vertices (flat-shaded export); on the
    # right edge the copies are 0.3 um off, under the weld tolerance (1e-6 x the 1.17 m diagonal).
    for i in range(n):
        (ax, az), (bx, bz) = boundary[i], boundary[(i + 1) % n]
        off = 3e-7 if ax == hx and bx == hx else 0.0
        v = [prim.vertex((ax + off, hy, az)), prim.vertex((bx + off, hy, bz)),
             prim.vertex((bx + off, -hy, bz)), prim.vertex((ax + off, -hy, az))]
        quad(prim, v[0], v[3], v[2], v[1])
    check_outward(prim, (0.0, 0.0, 0.0))

    # Triangles that welding and the degenerate filter must remove.
    left = [top[boundary.index((-hx, z))] for z in (-0.1, 0.0, 0.1)]
    prim.tri(*left)                                        # three exactly collinear corners
    prim.tri(top[0], top[3], top[3])                       # a repeated index
    dup = prim.vertex(prim.positions[top[n - 1]])
    prim.tri(top[0], top[n - 1], dup)                      # a zero-length edge (same position)
    near = prim.vertex(sub(prim.positions[top[1]], (-4e-7, 0.0, 0.0)))
    prim.tri(top[0], top[1], near)                         # a 0.4 um edge: welded away
    return prim


def sliver_strip():
    pitch, columns = 0.006, 100          # 0.6 m across
    hz = 0.25
    xs = [-0.3 + i * pitch for i in range(columns + 1)]
    prim = Primitive(mode=5)
    front = [prim.vertex((x, 0.0, hz)) for x in xs]
    back = [prim.vertex((x, 0.0, -hz)) for x in xs]
    k = columns // 2
    first = []
    for i in range(0, k + 1):
        first += [back[i], front[i]]
    second = []
    for i in range(k, columns + 1):
        second += [back[i], front[i]]
    # Join: repeat the last index of the first strip and the first of the second, keeping the
    # second strip's winding parity (both strips have an even length).
    prim.indices = first + [first[-1], second[0]] + second
    # Check: every non-degenerate strip triangle faces +y once the odd ones are flipped.
    idx = prim.indices
    for t in range(len(idx) - 2):
        a, b, c = idx[t:t + 3] if t % 2 == 0 else (idx[t + 1], idx[t], idx[t + 2])
        if len({a, b, c}) < 3:
            continue
        pa, pb, pc = (prim.positions[i] for i in (a, b, c))
        assert cross(sub(pb, pa), sub(pc, pa))[1] > 0.0, "strip triangle %d faces down" % t
    return prim


# --- open and non-manifold ------------------------------------------------------------------------

def box_corners(lo, hi):
    return [(x, y, z) for x in (lo[0], hi[0]) for y in (lo[1], hi[1]) for z in (lo[2], hi[2])]


# Faces of a box as corner indices into box_corners (index = 4x + 2y + z), counter-clockwise seen
# from outside.
BOX_FACES = {
    "-x": (0, 1, 3, 2), "+x": (4, 6, 7, 5),
    "-y": (0, 4, 5, 1), "+y": (2, 3, 7, 6),
    "-z": (0, 2, 6, 4), "+z": (1, 5, 7, 3),
}


def add_box(prim, lo, hi, faces=BOX_FACES.keys()):
    idx = [prim.vertex(p) for p in box_corners(lo, hi)]
    for f in faces:
        quad(prim, *(idx[i] for i in BOX_FACES[f]))


def open_box():
    prim = Primitive()
    add_box(prim, (-0.3, -0.2, -0.3), (0.3, 0.2, 0.3), ["-x", "+x", "-y", "-z"])
    check_outward(prim, (0.0, 0.0, 0.0))
    return prim


def fan():
    prim = Primitive(mode=6)
    r, segments = 0.3, 12
    prim.vertex((0.0, 0.0, 0.0))
    # Clockwise seen from above (decreasing angle from +x towards +z): the fan faces -y.
    for j in range(segments + 1):
        a = 2.0 * math.pi * j / segments
        prim.vertex((r * math.cos(a), 0.0, r * math.sin(a)))
    prim.indices = list(range(segments + 2))
    for j in range(segments):
        t = (0, j + 1, j + 2)
        pa, pb, pc = (prim.positions[i] for i in t)
        assert cross(sub(pb, pa), sub(pc, pa))[1] < 0.0, "fan triangle %d faces up" % j
    return prim


def fins():
    prim = Primitive()
    half, depth = 0.3, 0.3
    s0 = prim.vertex((-half, 0.0, 0.0))
    s1 = prim.vertex((half, 0.0, 0.0))
    for deg in (0.0, 55.0, 115.0, 165.0):
        a = math.radians(deg)
        d = (0.0, depth * math.sin(a), depth * math.cos(a))
        t0 = prim.vertex((-half, d[1], d[2]))
        t1 = prim.vertex((half, d[1], d[2]))
        quad(prim, s0, s1, t1, t0)
    return prim


def tee():
    prim = Primitive()
    hx, hz, height = 0.35, 0.25, 0.25
    # Plate in y = 0 with its centre line z = 0 as edges; each half is two triangles.
    row = [[prim.vertex((x, 0.0, z)) for x in (-hx, hx)] for z in (-hz, 0.0, hz)]
    for r in range(2):
        quad(prim, row[r][0], row[r + 1][0], row[r + 1][1], row[r][1])
    # Fin in z = 0 standing on the centre line, reusing its vertices.
    t0 = prim.vertex((-hx, height, 0.0))
    t1 = prim.vertex((hx, height, 0.0))
    quad(prim, row[1][0], row[1][1], t1, t0)
    return prim


def cubes_edge():
    prim = Primitive()
    s = 0.3
    add_box(prim, (-s, -s / 2, -s / 2), (0.0, s / 2, s / 2))
    add_box(prim, (0.0, s / 2, -s / 2), (s, 3 * s / 2, s / 2))
    return prim


def main():
    here = os.path.dirname(os.path.abspath(__file__))
    out = sys.argv[1] if len(sys.argv) > 1 else os.path.join(here, "..", "data", "stability")
    os.makedirs(out, exist_ok=True)
    meshes = {
        "sliver-slab": [sliver_slab()],
        "sliver-strip": [sliver_strip()],
        "open-box": [open_box()],
        "fan": [fan()],
        "fins": [fins()],
        "tee": [tee()],
        "cubes-edge": [cubes_edge()],
    }
    for name, prims in meshes.items():
        path = os.path.join(out, name + ".gltf")
        write_gltf(path, prims, name)
        print("%s: %d vertices, %d indices" % (
            os.path.normpath(path), sum(len(p.positions) for p in prims),
            sum(len(p.indices) for p in prims)))


if __name__ == "__main__":
    main()
