#!/usr/bin/env python3
"""A spray stress case: a real cache's frames with N droplets added above the fluid, each an
icosphere (42 vertices, radius 1.0-1.8 of the cache's units) on a lattice 6 units apart, moving
ballistically with its own small velocity, so droplets never touch one another. Measures how the
tracker copes with a frame that is mostly droplets (docs/performance.md).

  python add_droplets.py SRC DST N FIRST COUNT
      SRC: a folder of fluid_mesh_NNNN.bobj.gz frames; DST gets fluid_mesh_0000 ... COUNT-1,
      frames FIRST ... FIRST+COUNT-1 of SRC with the droplets added (numpy seed 7).
"""
import gzip, os, struct, sys
import numpy as np

if len(sys.argv) != 6:
    sys.exit(__doc__)
src, dst, n, first, count = sys.argv[1], sys.argv[2], *map(int, sys.argv[3:])


def read_bobj(path):
    data = gzip.open(path).read()
    vertices = struct.unpack_from("<i", data, 0)[0]
    at = 4
    positions = np.frombuffer(data, "<f4", 3 * vertices, at).reshape(-1, 3)
    at += 12 * vertices
    at += 4 + 12 * struct.unpack_from("<i", data, at)[0]
    triangles = struct.unpack_from("<i", data, at)[0]
    return positions, np.frombuffer(data, "<i4", 3 * triangles, at + 4).reshape(-1, 3)


def write_bobj(path, positions, triangles):
    body = (struct.pack("<i", len(positions)) + positions.astype("<f4").tobytes()
            + struct.pack("<i", 0) + struct.pack("<i", len(triangles))
            + triangles.astype("<i4").tobytes())
    with open(path, "wb") as fh:
        fh.write(gzip.compress(body, mtime=0))


def icosphere():
    t = (1 + 5 ** 0.5) / 2
    v = [(-1, t, 0), (1, t, 0), (-1, -t, 0), (1, -t, 0), (0, -1, t), (0, 1, t), (0, -1, -t),
         (0, 1, -t), (t, 0, -1), (t, 0, 1), (-t, 0, -1), (-t, 0, 1)]
    f = [(0, 11, 5), (0, 5, 1), (0, 1, 7), (0, 7, 10), (0, 10, 11), (1, 5, 9), (5, 11, 4),
         (11, 10, 2), (10, 7, 6), (7, 1, 8), (3, 9, 4), (3, 4, 2), (3, 2, 6), (3, 6, 8), (3, 8, 9),
         (4, 9, 5), (2, 4, 11), (6, 2, 10), (8, 6, 7), (9, 8, 1)]
    v = [np.array(p) / np.linalg.norm(p) for p in v]
    middle, faces = {}, []
    def mid(a, b):
        key = (min(a, b), max(a, b))
        if key not in middle:
            p = v[a] + v[b]
            v.append(p / np.linalg.norm(p))
            middle[key] = len(v) - 1
        return middle[key]
    for a, b, c in f:
        ab, bc, ca = mid(a, b), mid(b, c), mid(c, a)
        faces += [(a, ab, ca), (b, bc, ab), (c, ca, bc), (ab, bc, ca)]
    return np.array(v), np.array(faces)


ball, faces = icosphere()
rng = np.random.default_rng(7)
positions, _ = read_bobj(os.path.join(src, "fluid_mesh_%04d.bobj.gz" % first))
lo, hi = positions.min(0), positions.max(0)
columns = [(x, z) for x in range(int((hi[0] - lo[0]) / 6)) for z in range(int((hi[2] - lo[2]) / 6))]
lattice = np.array([(x, y, z) for y in range(1 + n // max(len(columns), 1)) for x, z in columns])[:n]
start = np.array([lo[0] + 3, hi[1] + 4, lo[2] + 3]) + 6 * lattice + rng.uniform(-1, 1, (n, 3))
velocity = np.array([0.5, 0.3, -0.2]) + rng.normal(0, 0.1, (n, 3))
radius = rng.uniform(1.0, 1.8, n)
os.makedirs(dst, exist_ok=True)
for k in range(count):
    positions, triangles = read_bobj(os.path.join(src, "fluid_mesh_%04d.bobj.gz" % (first + k)))
    centres = start + velocity * k + np.array([0, -0.15, 0]) * k * k
    parts_p, parts_t, offset = [positions], [triangles], len(positions)
    for c, r in zip(centres, radius):
        parts_p.append(ball * r + c)
        parts_t.append(faces + offset)
        offset += len(ball)
    write_bobj(os.path.join(dst, "fluid_mesh_%04d.bobj.gz" % k),
               np.concatenate(parts_p), np.concatenate(parts_t))
