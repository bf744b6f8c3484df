#!/usr/bin/env python3
# Writes the serialized fuzz seeds (tests/fuzz/corpus/serialized/) in Mitsuba's format
# (docs/mitsuba.md, src/scene/load_serialized.cpp): run from the repository's root.
import math, struct, zlib

def shape(pos, idx, nrm=None, uv=None, col=None, dbl=False, name=b"seed", version=4):
    flags = (1 if nrm else 0) | (2 if uv else 0) | (8 if col else 0) | (0x2000 if dbl else 0x1000)
    f = "d" if dbl else "f"
    raw = struct.pack("<I", flags) + (name + b"\0" if version == 4 else b"")
    raw += struct.pack("<QQ", len(pos) // 3, len(idx) // 3)
    for a in (pos, nrm, uv, col):
        if a:
            raw += struct.pack("<%d%s" % (len(a), f), *a)
    raw += struct.pack("<%dI" % len(idx), *idx)
    return struct.pack("<HH", 0x041C, version) + zlib.compress(raw, 9)

def serialized(shapes, version=4):
    out, offsets = b"", []
    for s in shapes:
        offsets.append(len(out))
        out += s
    out += b"".join(struct.pack("<Q" if version == 4 else "<I", o) for o in offsets)
    return out + struct.pack("<I", len(shapes))

def grid(n, z):  # an n x n grid of quads with normals and uv
    pos, nrm, uv, idx = [], [], [], []
    for j in range(n + 1):
        for i in range(n + 1):
            x, y = i / n, j / n
            pos += [x, y, z(x, y)]
            nrm += [0.0, 0.0, 1.0]
            uv += [x, y]
    for j in range(n):
        for i in range(n):
            a = j * (n + 1) + i
            idx += [a, a + 1, a + n + 2, a, a + n + 2, a + n + 1]
    return pos, nrm, uv, idx

root = "tests/fuzz/corpus/serialized/"
tri = ([0.0, 0, 0, 1, 0, 0, 0, 1, 0], [0, 1, 2])
pos, nrm, uv, idx = grid(4, lambda x, y: 0.1 * math.sin(3 * x + y))
open(root + "grid-v4-float.serialized", "wb").write(serialized([shape(pos, idx, nrm, uv, name=b"grid")]))
open(root + "two-shapes-v4-double.serialized", "wb").write(serialized(
    [shape(*tri, dbl=True, col=[1.0] * 9), shape(pos, idx, uv=uv, dbl=True, name=b"grid \xc3\xa9")]))
open(root + "two-shapes-v3-float.serialized", "wb").write(serialized(
    [shape(*tri, version=3), shape(pos, idx, nrm, version=3)], version=3))
