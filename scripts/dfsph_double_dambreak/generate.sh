#!/usr/bin/env bash
# Usage: [SCENE=pool_crown] generate.sh OUT. Simulates and surfaces the DFSPH double dam break (or
# the scene SCENE names) into the folder OUT: OUT/frames/fluid_mesh_0000.obj … fluid_mesh_0044.obj.
# Needs Python 3.11 and PyPI; about 4 min of simulation and 30 s of meshing on 2 cores (pool_crown:
# 1 min). See README.md.
set -euo pipefail
if [ $# -ne 1 ]; then
  echo "usage: $0 OUT (the folder that receives the particles and the frames)" >&2
  exit 2
fi
here="$(cd "$(dirname "$0")" && pwd)"
out="$(mkdir -p "$1" && cd "$1" && pwd)"
if [ ! -x "$out/.venv/bin/python" ]; then
  python3 -m venv "$out/.venv"
  "$out/.venv/bin/pip" install -q pysplishsplash==2.19.0 pysplashsurf==0.14.1.0 numpy
fi
# The pysplishsplash 2.19.0 wheel bundles its own libGLdispatch, which the system's libGLX then
# calls into on import and crashes; preloading the system's copy avoids the mix (nothing is drawn).
glx=/lib/x86_64-linux-gnu/libGLdispatch.so.0
LD_PRELOAD="$( [ -e "$glx" ] && echo "$glx" || true )" OMP_NUM_THREADS=2 \
  "$out/.venv/bin/python" "$here/generate.py" sim "$out"
RAYON_NUM_THREADS=2 "$out/.venv/bin/python" "$here/generate.py" mesh "$out"
echo "frames in $out/frames"
