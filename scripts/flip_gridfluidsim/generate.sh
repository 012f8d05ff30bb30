#!/usr/bin/env bash
# Usage: [SCENE=pool_drop|two_columns] [SUBDIVISION=N] generate.sh OUT. Builds GridFluidSim3D (a PIC/FLIP liquid
# solver with its own surface mesher), runs the scene SCENE names (default pool_drop) and leaves
# its frames in OUT/frames: 000000.ply … Needs git, cmake ≥ 3.5, g++, python3 and the OpenCL
# headers (Debian: opencl-headers opencl-clhpp-headers ocl-icd-opencl-dev); no OpenCL device is
# used. About 2 min (pool_drop) or 6 min (two_columns) on 2 cores. See README.md.
set -euo pipefail
if [ $# -ne 1 ]; then
  echo "usage: $0 OUT (the folder that receives the solver and the frames)" >&2
  exit 2
fi
here="$(cd "$(dirname "$0")" && pwd)"
scene="${SCENE:-pool_drop}"
if [ ! -f "$here/scenes/$scene.cpp" ]; then
  echo "unknown SCENE '$scene': expected one of $(ls "$here/scenes" | grep '\.cpp$' | sed 's/\.cpp$//' | xargs)" >&2
  exit 2
fi
out="$(mkdir -p "$1" && cd "$1" && pwd)"
solver="$out/GridFluidSim3D"
if [ ! -d "$solver" ]; then
  git clone -q "${GFS_SOURCE:-https://github.com/rlguy/GridFluidSim3D}" "$solver"
  git -C "$solver" checkout -q 5dbd0ca028fc6a7ec8d9e9db56501a814c0f09f1
  python3 "$here/patch.py" "$solver"
fi
cp "$here/scenes/$scene.cpp" "$solver/src/main.cpp"
cp "$here/scenes/scene.h" "$solver/src/scene.h"
mkdir -p "$solver/build"
(cd "$solver/build" &&
  cmake .. -DCMAKE_POLICY_VERSION_MINIMUM=3.5 -DCMAKE_CXX_FLAGS="-fpermissive -w -include limits" > cmake.log &&
  make -j2 fluidsim > make.log)
run="$solver/build/fluidsim"
rm -rf "$run/output" && mkdir -p "$run/output/bakefiles" "$run/output/logs" "$run/output/temp" "$run/output/savestates"
# No OpenCL device: the scenes run the CPU paths; an ICD that cannot build kernels is kept away.
(cd "$run" && OCL_ICD_VENDORS=/nonexistent ./fluidsim > "$out/$scene.log")
rm -rf "$out/frames" && mkdir -p "$out/frames"
cp "$run"/output/bakefiles/*.ply "$out/frames/"
echo "frames in $out/frames"
