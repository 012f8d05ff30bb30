"""libigl's signed distance on the narrow-band queries of `examples/band_reference.rs`, timed in
the same run as ours (issue: grid stage, bar 4). Needs `pip install libigl numpy`.

    python3 benches/reference/libigl_band.py [RUNS]

Builds and runs the example (which writes the mesh and the band corners to a temporary folder and
prints its own timings), then times libigl (pseudonormal sign, as fast as libigl's signs get) on
exactly those corners, interleaved, and checks that both give the same distances.
"""
import subprocess
import sys
import tempfile
import time

import igl
import numpy as np

runs = int(sys.argv[1]) if len(sys.argv) > 1 else 3
with tempfile.TemporaryDirectory() as d:
    ours = []
    theirs = []
    for r in range(runs):
        out = subprocess.run(
            ["cargo", "run", "--quiet", "--release", "--example", "band_reference", "--", d, "3"],
            check=True, capture_output=True, text=True).stdout
        ours += [float(line.split()[-2]) for line in out.splitlines()]
        V = np.fromfile(f"{d}/vertices.f64", "<f8").reshape(-1, 3)
        F = np.fromfile(f"{d}/triangles.i32", "<i4").reshape(-1, 3).astype(np.int64)
        B = np.fromfile(f"{d}/band.f64", "<f8").reshape(-1, 4)
        Q = np.ascontiguousarray(B[:, :3])
        start = time.perf_counter()
        S = igl.signed_distance(Q, V, F, igl.SIGNED_DISTANCE_TYPE_PSEUDONORMAL)[0]
        theirs.append((time.perf_counter() - start) * 1e3)
    print(f"{len(V)} vertices, {len(F)} triangles, {len(Q)} band corners")
    print("surftrack ms:", " ".join(f"{t:.1f}" for t in ours))
    print("libigl ms:   ", " ".join(f"{t:.1f}" for t in theirs))
    print(f"best: surftrack {min(ours):.1f} ms, libigl {min(theirs):.1f} ms, "
          f"ratio {min(theirs) / min(ours):.2f}x")
    print("largest |distance| difference:", np.abs(np.abs(S) - np.abs(B[:, 3])).max())
    print("sign agreement:", np.mean(np.sign(S) == np.sign(B[:, 3])))
