#!/usr/bin/env python3
"""Real fluid sequences from a third solver: a SPlisHSPlasH (DFSPH) double dam break around a box
obstacle (or, with SCENE=pool_crown, a pool's splash crown and a falling block), surfaced per frame
with splashsurf. See README.md; `generate.sh OUT` runs both steps.

  python generate.py sim OUT    # OUT/particles/particles_NNNN.npy and OUT/scene.json
  python generate.py mesh OUT   # OUT/frames/fluid_mesh_NNNN.obj
"""
import json, os, sys, time
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


if __name__ == "__main__":
    {"sim": sim, "mesh": mesh}[sys.argv[1]]()
