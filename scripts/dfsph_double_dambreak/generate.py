#!/usr/bin/env python3
"""Real fluid sequences from a third solver: a SPlisHSPlasH (DFSPH) double dam break around a box
obstacle (or, with SCENE=pool_crown, a pool's splash crown and a falling block), surfaced per frame
with splashsurf. See README.md; `generate.sh OUT` runs both steps.

  python generate.py sim OUT    # OUT/particles/particles_NNNN.npy and OUT/scene.json
  python generate.py mesh OUT   # OUT/frames/fluid_mesh_NNNN.obj
  python generate.py nets OUT   # OUT/nets/fluid_NNNN.bobj.gz, surface nets (FRAMES=a:b for some)
"""
import gzip, json, os, struct, sys, time
import numpy as np

OUT = os.path.abspath(sys.argv[2]) if len(sys.argv) > 2 else sys.exit(__doc__)
R = 0.0075            # particle radius (m); SPlisHSPlasH support radius = 4R
DT = 0.001            # fixed time step (s), no CFL adaptation
FPS = 40              # output frame rate
NFRAMES = 45          # frames 0..44, t = i/FPS
STEPS_PER_FRAME = round(1.0 / (FPS * DT))   # 25

# splashsurf settings (multiples of R where noted)
SMOOTHING_LENGTH = 2.0   # x R  (kernel compact support = 2 x smoothing length = 4R)
ISO = 0.6                # iso-surface threshold (fraction of rest density)

# The scenes (SCENE=...): the tank (centre, size), the obstacle (centre, turn about y, size), the
# water blocks and the marching-cubes cell (x R, CUBE_SIZE overrides it).
SCENES = {
    # Two columns in opposite corners collapse around a box on the floor (README.md).
    "double_dambreak": {
        "tank": ([0, 0.6, 0], [1.0, 1.2, 0.6], [40, 48, 24]),
        "obstacle": ([0.0, 0.075, 0.0], 0.4),
        "blocks": [([-0.485, 0.015, -0.285], [-0.265, 0.60, 0.05]),
                   ([0.265, 0.015, -0.05], [0.485, 0.45, 0.285])],
        "cube": 1.0,
    },
    # A shallow pool whose lattice overlaps a post: the solver expels the overlapping particles in
    # the first steps, throwing a crown of sheets and droplets against the walls, while a block of
    # water falls into the pool (merging at frame 11) (README.md).
    "pool_crown": {
        "tank": ([0, 0.4, 0], [0.6, 0.8, 0.6], [30, 40, 30]),
        "obstacle": ([0.12, 0.075, -0.1], 0.7),
        "blocks": [([-0.285, 0.015, -0.285], [0.285, 0.10, 0.285]),
                   ([-0.13, 0.42, -0.07], [0.05, 0.62, 0.11])],
        "cube": 0.8,
    },
}
SCENE = SCENES[os.environ.get("SCENE", "double_dambreak")]
CUBE_SIZE = float(os.environ.get("CUBE_SIZE", SCENE["cube"]))  # x R


def scene(models):
    box = os.path.join(models, "UnitBox.obj")
    (tank_at, tank_size, tank_map), (post_at, post_turn) = SCENE["tank"], SCENE["obstacle"]
    return {
        "Configuration": {
            "particleRadius": R,
            "simulationMethod": 4,            # DFSPH
            "gravitation": [0, -9.81, 0],
            "timeStepSize": DT,
            "cflMethod": 0,                   # fixed time step
            "boundaryHandlingMethod": 2,      # Bender et al. 2019 volume maps
            "kernel": 1, "gradKernel": 1,     # cubic spline
            "enableZSort": False,
            "stopAt": NFRAMES / FPS + 0.5 * DT,
            "DFSPH": {"minIterations": 2, "maxIterations": 100, "maxError": 0.01,
                      "maxIterationsV": 100, "maxErrorV": 0.1,
                      "enableDivergenceSolver": True},
        },
        "Materials": [{
            "id": "Fluid", "density0": 1000, "viscosityMethod": 1,
            "viscosity": 0.01,
            "Standard viscosity": {"viscosity": 0.01},
        }],
        "RigidBodies": [
            {   # tank: its interior is the box, floor at y = 0
                "id": 1, "geometryFile": box, "translation": tank_at,
                "rotationAxis": [1, 0, 0], "rotationAngle": 0,
                "scale": tank_size, "isDynamic": False, "isWall": True,
                "invertSDF": True, "mapInvert": True, "mapThickness": 0.0,
                "mapResolution": tank_map,
            },
            {   # obstacle: box 0.10 x 0.15 x 0.10 on the floor
                "id": 2, "geometryFile": box, "translation": post_at,
                "rotationAxis": [0, 1, 0], "rotationAngle": post_turn,
                "scale": [0.10, 0.15, 0.10], "isDynamic": False, "isWall": False,
                "mapInvert": False, "mapThickness": 0.0,
                "mapResolution": [20, 30, 20],
            },
        ],
        "FluidBlocks": [{"denseMode": 0, "start": a, "end": b} for a, b in SCENE["blocks"]],
    }


def sim():
    import pysplishsplash as sph
    models = os.path.join(os.path.dirname(sys.executable), "data", "models")
    os.makedirs(os.path.join(OUT, "particles"), exist_ok=True)
    scene_file = os.path.join(OUT, "scene.json")
    with open(scene_file, "w") as f:
        json.dump(scene(models), f, indent=2)
    base = sph.Exec.SimulatorBase()
    base.init(useGui=False, sceneFile=scene_file, outputDir=os.path.join(OUT, "sim_out"),
              useCache=False, initialPause=False, stopAt=NFRAMES / FPS + 0.5 * DT)
    state = {"step": 0, "t0": time.time()}

    def dump(frame):
        sim_ = sph.Simulation.getCurrent()
        fm = sim_.getFluidModel(0)
        n = fm.numActiveParticles()
        pos = np.array([np.asarray(fm.getPosition(i)).reshape(3) for i in range(n)],
                       dtype=np.float32)
        np.save(os.path.join(OUT, "particles", "particles_%04d.npy" % frame), pos)
        t = sph.TimeManager.getCurrent().getTime()
        print("frame %d t=%.4f n=%d ymax=%.3f wall=%.1fs" %
              (frame, t, n, pos[:, 1].max(), time.time() - state["t0"]), flush=True)

    def cb():
        state["step"] += 1
        if state["step"] % STEPS_PER_FRAME == 0:
            f = state["step"] // STEPS_PER_FRAME
            if f < NFRAMES:
                dump(f)

    base.setTimeStepCB(cb)
    base.initSimulation()
    dump(0)
    base.runSimulation()
    base.cleanup()


def mesh():
    import pysplashsurf
    outdir = os.path.join(OUT, "frames")
    os.makedirs(outdir, exist_ok=True)
    for f in range(NFRAMES):
        pos = np.load(os.path.join(OUT, "particles", "particles_%04d.npy" % f)).astype(np.float64)
        mesh_out = reconstruct(pysplashsurf, pos)
        verts, tris = mesh_out
        write_obj(os.path.join(outdir, "fluid_mesh_%04d.obj" % f), verts, tris)
        print("frame %d: %d particles -> %d verts %d tris" % (f, len(pos), len(verts), len(tris)),
              flush=True)


def reconstruct(ps, pos):
    mwd, _rec = ps.reconstruction_pipeline(
        pos, particle_radius=R, rest_density=1000.0,
        smoothing_length=SMOOTHING_LENGTH, cube_size=CUBE_SIZE,
        iso_surface_threshold=ISO,
        multi_threading=True, subdomain_grid=True,
        mesh_cleanup=True,            # Moore & Warren 1992 compact isocontours
        decimate_barnacles=False, mesh_smoothing_iters=None,
        generate_quads=False, compute_normals=False,
        check_mesh_closed=True, check_mesh_manifold=True, check_mesh_orientation=False)
    m = mwd.mesh
    return np.asarray(m.vertices, dtype=np.float64), np.asarray(m.triangles, dtype=np.int64)


def write_obj(path, v, t):
    with open(path, "w") as fh:
        fh.write("".join("v %.6f %.6f %.6f\n" % tuple(p) for p in v))
        fh.write("".join("f %d %d %d\n" % (a + 1, b + 1, c + 1) for a, b, c in t))


def nets():
    """The same particles surfaced by surface nets instead of marching cubes: one vertex per grid
    cell the iso-surface crosses (the mean of its edge crossings), one quad per crossed grid edge,
    split along its shorter diagonal. Like OpenVDB's volume-to-mesh, a dual mesher joins the sheets
    that pass through one cell at one vertex, so a splash's touching parts come out non-manifold.
    The field is splashsurf's: the cubic-spline SPH density at smoothing length 2 R over the density
    of the particle lattice, iso-surface at ISO, on cells of CUBE_SIZE x R."""
    outdir = os.path.join(OUT, "nets")
    os.makedirs(outdir, exist_ok=True)
    first, last = (int(x) for x in os.environ.get("FRAMES", "0:%d" % NFRAMES).split(":"))
    for f in range(first, last):
        pos = np.load(os.path.join(OUT, "particles", "particles_%04d.npy" % f)).astype(np.float64)
        verts, tris = surface_nets(pos, CUBE_SIZE * R)
        write_bobj(os.path.join(outdir, "fluid_%04d.bobj.gz" % f), verts, tris)
        print("frame %d: %d particles -> %d verts %d tris" % (f, len(pos), len(verts), len(tris)),
              flush=True)


def cubic_spline(q):
    """The cubic spline kernel's shape at q = r / h (support 2 h), 1 at q = 0."""
    return np.where(q < 1, 1 - 1.5 * q**2 + 0.75 * q**3, np.where(q < 2, 0.25 * (2 - q)**3, 0.0))


def surface_nets(pos, cell):
    h = SMOOTHING_LENGTH * R
    lo = np.floor((pos.min(0) - 3 * h) / cell) * cell
    n = (np.ceil((pos.max(0) + 3 * h - lo) / cell)).astype(int) + 1
    rho = np.zeros(n)
    base = np.floor((pos - lo) / cell).astype(int)
    reach = int(np.ceil(2 * h / cell))
    for d in np.ndindex(*(2 * reach + 2,) * 3):
        idx = base + np.array(d) - reach
        w = cubic_spline(np.linalg.norm(lo + idx * cell - pos, axis=1) / h)
        m = w > 0
        np.add.at(rho, tuple(idx[m].T), w[m])
    lattice = np.array(list(np.ndindex(7, 7, 7))) - 3
    full = cubic_spline(np.linalg.norm(lattice * 2 * R, axis=1) / h).sum()
    phi = rho / full - ISO
    inside = phi > 0
    cells = n - 1
    corners = [np.array(c) for c in np.ndindex(2, 2, 2)]
    total, crossings = np.zeros(tuple(cells) + (3,)), np.zeros(tuple(cells))
    at = lambda o: tuple(slice(o[k], o[k] + cells[k]) for k in range(3))
    for u, v in [(u, v) for u in range(8) for v in range(u + 1, 8)
                 if np.abs(corners[u] - corners[v]).sum() == 1]:
        a, b = phi[at(corners[u])], phi[at(corners[v])]
        cross = (a > 0) != (b > 0)
        t = np.where(cross, a / np.where(cross, a - b, 1.0), 0.0)
        point = corners[u] + t[..., None] * (corners[v] - corners[u])
        total += np.where(cross[..., None], point, 0.0)
        crossings += cross
    active = crossings > 0
    index = -np.ones(tuple(cells), int)
    index[active] = np.arange(active.sum())
    verts = lo + (np.argwhere(active) + total[active] / crossings[active][:, None]) * cell
    tris = []
    for axis in range(3):
        step = np.eye(3, dtype=int)[axis]
        a = inside[tuple(slice(0, n[k] - step[k]) for k in range(3))]
        b = inside[tuple(slice(step[k], n[k]) for k in range(3))]
        edges = np.argwhere(a != b)
        u, w = [k for k in range(3) if k != axis]
        edges = edges[(edges[:, u] >= 1) & (edges[:, w] >= 1)
                      & (edges[:, u] < cells[u]) & (edges[:, w] < cells[w])]
        def around(du, dw):
            c = edges.copy()
            c[:, u] -= du
            c[:, w] -= dw
            return index[tuple(c.T)]
        quad = np.stack([around(1, 1), around(0, 1), around(0, 0), around(1, 0)], 1)
        # Facing outward: from the inside corner to the outside one, counter-clockwise seen from
        # outside (the (u, w) order is cyclic except for the y axis).
        outward = ~a[tuple(edges.T)] if axis != 1 else a[tuple(edges.T)]
        quad[outward] = quad[outward][:, ::-1]
        short = (np.linalg.norm(verts[quad[:, 0]] - verts[quad[:, 2]], axis=1)
                 <= np.linalg.norm(verts[quad[:, 1]] - verts[quad[:, 3]], axis=1))
        tris.append(np.where(short[:, None], quad[:, [0, 1, 2]], quad[:, [0, 1, 3]]))
        tris.append(np.where(short[:, None], quad[:, [0, 2, 3]], quad[:, [1, 2, 3]]))
    return verts, np.concatenate(tris)


def write_bobj(path, v, t):
    """Blender's fluid cache: vertex count and positions, no normals, triangle count and corners."""
    body = (struct.pack("<i", len(v)) + np.asarray(v, "<f4").tobytes() + struct.pack("<i", 0)
            + struct.pack("<i", len(t)) + np.asarray(t, "<i4").tobytes())
    with open(path, "wb") as fh:
        fh.write(gzip.compress(body, mtime=0))


if __name__ == "__main__":
    {"sim": sim, "mesh": mesh, "nets": nets}[sys.argv[1]]()
