#!/usr/bin/env python3
"""Second real fluid sequence for surftrack: two liquid drops falling into a pool.

Solver: 3-D MLS-MPM weakly compressible fluid (Hu et al. 2018, "A moving least squares
material point method", the scheme of Taichi's own examples/simulation/mpm3d.py), run with the
Taichi package (pip install taichi) on one CPU thread.  Surfacing: per frame the normalised SPH
colour field rho(x) = sum_j W_poly6(|x - x_j|, R) / rho0 on a padded grid, marching cubes
(scikit-image, Lewiner) at rho = ISO; the liquid is rho > ISO, triangles CCW seen from outside.
Frames are written as Blender/Mantaflow `.bobj.gz` (no normals), coordinates in units of the
surfacing grid spacing H, quantised to 1/256 of a cell so they compress.

Usage (from the repository root, in a Python env with taichi, numpy, scipy, scikit-image):

    OMP_NUM_THREADS=1 python tests/data/droppool_mpm_taichi/generate.py \
        --cache /tmp/droppool_cache.npz --out tests/data/droppool_mpm_taichi

This is a data generator only: nothing in the Rust build or CI runs it.
"""

import argparse
import gzip
import json
import os
import struct
import sys
import time

import numpy as np

# ---------------------------------------------------------------------------------------------
# Scene and solver parameters (SI units, domain [0,1]^3, gravity -y).
N_GRID = 64                       # MPM grid cells per axis
DX = 1.0 / N_GRID
DT = 2e-4                         # MPM time step
E = 400.0                         # bulk stiffness of the weakly compressible fluid (c = 20 m/s);
                                  # pressure/rho = E * (1 - J), J clamped to <= 1 (no tension)
GRAVITY = 9.8
PPC_SPACING = DX / 2              # initial particle spacing: 8 particles per cell
P_VOL = PPC_SPACING ** 3
P_RHO = 1.0
P_MASS = P_VOL * P_RHO
FLOOR = 3                         # floor cells (velocity clamped below)
TANK_LO, TANK_HI = 16, 48         # tank walls in x and z, in cells (0.25 m .. 0.75 m)
POOL_DEPTH = 0.14                 # pool depth above the floor, m
# drops: (centre, radius, velocity)
DROPS = [
    ((0.47, 0.36, 0.50), 0.075, (0.0, -1.5, 0.0)),
    ((0.58, 0.56, 0.44), 0.050, (-0.3, -1.5, 0.3)),
]
SEED = 1
FRAME_DT = 1.0 / 100.0            # simulated seconds between cached frames
SIM_FRAMES = 90

# Surfacing parameters.
H = 1.0 / 80.0                    # marching-cubes grid spacing, m
R = 2.0 * H                       # poly6 support radius
ISO = 0.35
PAD = 3                           # empty cells around the particle bounds
QUANT = 256                       # vertex coordinates rounded to 1/QUANT of a cell


# ---------------------------------------------------------------------------------------------
def initial_particles():
    rng = np.random.default_rng(SEED)
    s = PPC_SPACING
    pts, vel = [], []
    # pool: a jittered lattice filling the tank up to POOL_DEPTH
    lo, hi = TANK_LO * DX, TANK_HI * DX
    y0 = FLOOR * DX
    xs = np.arange(lo + s / 2, hi, s)
    ys = np.arange(y0 + s / 2, y0 + POOL_DEPTH, s)
    g = np.stack(np.meshgrid(xs, ys, xs, indexing="ij"), -1).reshape(-1, 3)
    pts.append(g)
    vel.append(np.zeros_like(g))
    for c, r, v in DROPS:
        c = np.asarray(c)
        a = np.arange(-r, r + s, s)
        g = np.stack(np.meshgrid(a, a, a, indexing="ij"), -1).reshape(-1, 3)
        g = g[np.linalg.norm(g, axis=1) <= r] + c
        pts.append(g)
        vel.append(np.tile(np.asarray(v, float), (len(g), 1)))
    x = np.concatenate(pts)
    x += rng.uniform(-0.1 * s, 0.1 * s, x.shape)
    return x.astype(np.float32), np.concatenate(vel).astype(np.float32)


def simulate(cache):
    import taichi as ti

    ti.init(arch=ti.cpu, cpu_max_num_threads=1, default_fp=ti.f32, random_seed=SEED)
    x0, v0 = initial_particles()
    n = len(x0)
    print(f"simulate: {n} particles, taichi {ti.__version__}", flush=True)

    F_x = ti.Vector.field(3, float, n)
    F_v = ti.Vector.field(3, float, n)
    F_C = ti.Matrix.field(3, 3, float, n)
    F_J = ti.field(float, n)
    F_grid_v = ti.Vector.field(3, float, (N_GRID,) * 3)
    F_grid_m = ti.field(float, (N_GRID,) * 3)
    lo = ti.Vector([TANK_LO, FLOOR, TANK_LO])
    hi = ti.Vector([TANK_HI, N_GRID - 3, TANK_HI])

    @ti.kernel
    def substep():
        for I in ti.grouped(F_grid_m):
            F_grid_v[I] = ti.zero(F_grid_v[I])
            F_grid_m[I] = 0
        for p in F_x:
            Xp = F_x[p] / DX
            base = int(Xp - 0.5)
            fx = Xp - base
            w = [0.5 * (1.5 - fx) ** 2, 0.75 - (fx - 1) ** 2, 0.5 * (fx - 0.5) ** 2]
            stress = -DT * 4 * E * P_VOL * (F_J[p] - 1) / DX**2
            affine = ti.Matrix.identity(float, 3) * stress + P_MASS * F_C[p]
            for offset in ti.static(ti.grouped(ti.ndrange(3, 3, 3))):
                dpos = (offset - fx) * DX
                weight = w[offset[0]][0] * w[offset[1]][1] * w[offset[2]][2]
                F_grid_v[base + offset] += weight * (P_MASS * F_v[p] + affine @ dpos)
                F_grid_m[base + offset] += weight * P_MASS
        for I in ti.grouped(F_grid_m):
            if F_grid_m[I] > 0:
                F_grid_v[I] /= F_grid_m[I]
            F_grid_v[I][1] -= DT * GRAVITY
            cond = (I < lo) & (F_grid_v[I] < 0) | (I > hi) & (F_grid_v[I] > 0)
            F_grid_v[I] = ti.select(cond, 0, F_grid_v[I])
        for p in F_x:
            Xp = F_x[p] / DX
            base = int(Xp - 0.5)
            fx = Xp - base
            w = [0.5 * (1.5 - fx) ** 2, 0.75 - (fx - 1) ** 2, 0.5 * (fx - 0.5) ** 2]
            new_v = ti.zero(F_v[p])
            new_C = ti.zero(F_C[p])
            for offset in ti.static(ti.grouped(ti.ndrange(3, 3, 3))):
                dpos = (offset - fx) * DX
                weight = w[offset[0]][0] * w[offset[1]][1] * w[offset[2]][2]
                g_v = F_grid_v[base + offset]
                new_v += weight * g_v
                new_C += 4 * weight * g_v.outer_product(dpos) / DX**2
            F_v[p] = new_v
            F_x[p] += DT * F_v[p]
            # tension-free equation of state: an expanding particle's J is clamped at 1, so the
            # fluid never pulls on itself (negative pressure) and splashes can break off freely
            F_J[p] = ti.min(F_J[p] * (1 + DT * new_C.trace()), 1.0)
            F_C[p] = new_C

    F_x.from_numpy(x0)
    F_v.from_numpy(v0)
    F_J.fill(1.0)
    steps = int(round(FRAME_DT / DT))
    frames = [F_x.to_numpy()]
    t0 = time.time()
    for f in range(1, SIM_FRAMES):
        for _ in range(steps):
            substep()
        frames.append(F_x.to_numpy())
        if f % 10 == 0:
            print(f"  sim frame {f}/{SIM_FRAMES - 1}  {time.time() - t0:.1f}s", flush=True)
    np.savez_compressed(
        cache, x=np.stack(frames).astype(np.float32), taichi_version=".".join(map(str, ti.__version__))
    )
    return ti.__version__


# ---------------------------------------------------------------------------------------------
def poly6_offsets():
    k = int(np.ceil(R / H))
    o = np.arange(-k, k + 1)
    return np.stack(np.meshgrid(o, o, o, indexing="ij"), -1).reshape(-1, 3)


def rest_density():
    """Kernel sum at a particle inside the initial lattice (normalises rho to ~1 in the bulk)."""
    s = PPC_SPACING
    k = int(np.ceil(R / s))
    a = np.arange(-k, k + 1) * s
    g = np.stack(np.meshgrid(a, a, a, indexing="ij"), -1).reshape(-1, 3)
    r2 = (g**2).sum(1) / R**2
    return float(np.sum(np.where(r2 < 1, (1 - r2) ** 3, 0)))


def field(x, origin, shape, rho0):
    """rho on grid nodes origin + H * (i, j, k): scatter each particle's poly6 to nearby nodes."""
    rho = np.zeros(int(np.prod(shape)), np.float64)
    base = np.floor((x - origin) / H).astype(np.int64)
    offs = poly6_offsets()
    for o in offs:
        node = base + o
        d = origin + node * H - x
        r2 = (d * d).sum(1) / (R * R)
        m = r2 < 1
        idx = np.ravel_multi_index(node[m].T, shape)
        rho += np.bincount(idx, weights=(1 - r2[m]) ** 3, minlength=rho.size)
    return (rho / rho0).reshape(shape)


def mesh_frame(x, rho0, origin, shape):
    from skimage import measure

    rho = field(x, origin, shape, rho0)
    # keep every node strictly off the iso value so no vertex lands on a grid node
    eps = 1e-4
    near = np.abs(rho - ISO) < eps
    rho[near] = ISO + np.where(rho[near] >= ISO, eps, -eps)
    verts, faces, _, _ = measure.marching_cubes(rho, ISO, method="lewiner", gradient_direction="descent")
    # quantise in cell units, keeping each vertex strictly inside its grid edge
    q = np.round(verts * QUANT)
    on_node = (np.mod(q, QUANT) == 0) & (np.abs(verts - np.round(verts)) > 1e-6)
    q = np.where(on_node & (verts > q / QUANT), q + 1, np.where(on_node, q - 1, q))
    verts = q / QUANT + origin / H  # world position / H
    faces = faces.astype(np.int32)
    # orientation: outward (CCW seen from outside) means positive signed volume
    v = verts[faces]
    vol = np.einsum("ij,ij->i", v[:, 0], np.cross(v[:, 1], v[:, 2])).sum() / 6
    if vol < 0:
        faces = faces[:, ::-1].copy()
    return verts.astype(np.float32), np.ascontiguousarray(faces), abs(vol)


def write_bobj_gz(path, verts, faces):
    buf = bytearray()
    buf += struct.pack("<i", len(verts))
    buf += verts.astype("<f4").tobytes()
    buf += struct.pack("<i", 0)
    buf += struct.pack("<i", len(faces))
    buf += faces.astype("<i4").tobytes()
    with open(path, "wb") as f:
        f.write(gzip.compress(bytes(buf), compresslevel=9, mtime=0))


def components_and_euler(verts, faces):
    from scipy.sparse import coo_matrix
    from scipy.sparse.csgraph import connected_components

    nv = len(verts)
    e = np.concatenate([faces[:, [0, 1]], faces[:, [1, 2]], faces[:, [2, 0]]])
    a = coo_matrix((np.ones(len(e)), (e[:, 0], e[:, 1])), shape=(nv, nv))
    ncomp, _ = connected_components(a, directed=False)
    edges = np.unique(np.sort(e, 1), axis=0)
    return int(ncomp), int(nv - len(edges) + len(faces))


def mesh_all(cache, out, first, stride, count, solver_version):
    d = np.load(cache)
    xs = d["x"][first : first + stride * count : stride].astype(np.float64)
    assert len(xs) == count, f"cache has too few frames for {first}+{stride}*{count}"
    rho0 = rest_density()
    lo = np.floor(xs.reshape(-1, 3).min(0) / H) - PAD
    hi = np.ceil(xs.reshape(-1, 3).max(0) / H) + PAD + 1
    origin = lo * H
    shape = tuple((hi - lo).astype(int) + 1)
    os.makedirs(out, exist_ok=True)
    for f in os.listdir(out):
        if f.endswith(".bobj.gz"):
            os.remove(os.path.join(out, f))
    stats = []
    for i, x in enumerate(xs):
        verts, faces, vol = mesh_frame(x, rho0, origin, shape)
        name = f"fluid_mesh_{i:04d}.bobj.gz"
        write_bobj_gz(os.path.join(out, name), verts, faces)
        nc, chi = components_and_euler(verts, faces)
        stats.append(dict(frame=i, vertices=len(verts), triangles=len(faces), components=nc, euler=chi))
        print(f"  frame {i:2d}: {len(verts):6d} verts {nc:3d} comps chi {chi}", flush=True)
    vc = [s["vertices"] for s in stats]
    cc = [s["components"] for s in stats]
    manifest = dict(
        name=os.path.basename(os.path.normpath(out)),
        description=(
            "Two liquid drops falling into a pool, MLS-MPM weakly compressible fluid (Taichi), "
            "normalised SPH colour field rho(x)=sum_j W_poly6(|x-x_j|,R)/rho0 on a grid of spacing H, "
            "marching cubes (skimage lewiner) at rho=iso; coordinates in units of H (metres = value * H); "
            "triangles CCW seen from outside."
        ),
        generator="generate.py",
        command=(
            "OMP_NUM_THREADS=1 python tests/data/droppool_mpm_taichi/generate.py "
            "--cache /tmp/droppool_cache.npz --out tests/data/droppool_mpm_taichi"
        ),
        simulation=dict(
            solver="MLS-MPM weakly compressible fluid (Hu et al. 2018; Taichi examples/simulation/mpm3d.py scheme)",
            taichi_version=solver_version,
            n_particles=int(xs.shape[1]),
            n_grid=N_GRID,
            dt=DT,
            E=E,
            gravity=GRAVITY,
            particle_spacing=PPC_SPACING,
            tank_xz=[TANK_LO * DX, TANK_HI * DX],
            floor_y=FLOOR * DX,
            pool_depth=POOL_DEPTH,
            drops=[dict(centre=c, radius=r, velocity=v) for c, r, v in DROPS],
            seed=SEED,
            frame_dt=FRAME_DT,
            threads=1,
        ),
        surfacing=dict(grid_spacing_H=H, kernel_support_R=R, iso=ISO, rest_kernel_sum_rho0=rho0,
                       kernel="poly6 (1-r^2/R^2)^3", quantisation=f"1/{QUANT} cell", pad_cells=PAD),
        frame_count=count,
        sim_frame_first=first,
        sim_frame_stride=stride,
        vertex_counts=dict(min=min(vc), max=max(vc)),
        component_counts=dict(min=min(cc), max=max(cc)),
        frames=stats,
    )
    with open(os.path.join(out, "manifest.json"), "w") as f:
        json.dump(manifest, f, indent=1)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--cache", default="/tmp/droppool_cache.npz", help="particle cache (.npz); simulated if absent")
    ap.add_argument("--out", default=os.path.dirname(os.path.abspath(__file__)))
    ap.add_argument("--first", type=int, default=FIRST)
    ap.add_argument("--stride", type=int, default=STRIDE)
    ap.add_argument("--count", type=int, default=COUNT)
    ap.add_argument("--resimulate", action="store_true")
    a = ap.parse_args()
    if a.resimulate or not os.path.exists(a.cache):
        version = simulate(a.cache)
    version = str(np.load(a.cache)["taichi_version"])
    mesh_all(a.cache, a.out, a.first, a.stride, a.count, version)


FIRST, STRIDE, COUNT = 0, 2, 45

if __name__ == "__main__":
    sys.exit(main())
