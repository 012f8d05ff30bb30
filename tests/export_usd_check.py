#!/usr/bin/env python3
"""Checks a `surftrack export --usd` file with Pixar's USD (pip install usd-core) against the PLY
frames `surftrack export --ply` wrote from the same sequence: one time sample per frame, per-frame
point and face counts, topology, positions and `id` primvar equal to the PLY frames', velocities
equal to the definition (forward difference where the id lives on, else backward, else 0) within
1e-5 relative, and the carried channels as primvars. With --same-as OTHER, also that OTHER (the
same export in the other file form, .usda or .usdc) holds the same stage metadata and the same
attributes with the same metadata and values at every time sample.

usage: export_usd_check.py OUT.usd PLY_DIR [--fps 24] [--start 1] [--up-axis Y]
                           [--expect-color] [--expect-st] [--same-as OTHER.usd]
Prints one line per frame (and per compared attribute) and a summary; exits non-zero on the
first failed check.
"""

import argparse
import pathlib
import sys

import numpy as np
from pxr import Usd, UsdGeom

PLY_TYPES = {"float": "<f4", "double": "<f8", "uint": "<u4", "int": "<i4", "uchar": "u1"}


def read_ply(path):
    """Vertex properties (dict of arrays) and triangles of a binary little-endian PLY file."""
    data = path.read_bytes()
    end = data.index(b"end_header\n") + len(b"end_header\n")
    header = data[:end].decode("ascii").splitlines()
    assert "format binary_little_endian 1.0" in header, f"{path}: not binary little-endian"
    vertex_fields, counts, element = [], {}, None
    for line in header:
        words = line.split()
        if words[:1] == ["element"]:
            element = words[1]
            counts[element] = int(words[2])
        elif words[:1] == ["property"] and element == "vertex":
            vertex_fields.append((words[2], PLY_TYPES[words[1]]))
    vertices = np.frombuffer(data, vertex_fields, counts["vertex"], end)
    offset = end + vertices.nbytes
    faces = np.frombuffer(data, [("n", "u1"), ("v", "<i4", 3)], counts["face"], offset)
    assert np.all(faces["n"] == 3), f"{path}: not all faces are triangles"
    return vertices, faces["v"]


def velocities_by_definition(frames, fps):
    """(p(j+1) - p(j)) * fps where the id lives in j + 1, else (p(j) - p(j-1)) * fps, else 0."""
    positions = [np.stack([v["x"], v["y"], v["z"]], 1).astype(np.float64) for v, _ in frames]
    slots = [dict(zip(v["id"].tolist(), range(len(v)))) for v, _ in frames]
    result = []
    for j, (v, _) in enumerate(frames):
        out = np.zeros_like(positions[j])
        for i, vid in enumerate(v["id"].tolist()):
            if j + 1 < len(frames) and vid in slots[j + 1]:
                out[i] = (positions[j + 1][slots[j + 1][vid]] - positions[j][i]) * fps
            elif j > 0 and vid in slots[j - 1]:
                out[i] = (positions[j][i] - positions[j - 1][slots[j - 1][vid]]) * fps
        result.append(out)
    return result


def fail(message):
    print(f"FAIL: {message}")
    sys.exit(1)


def same_as(usd, other):
    """Every stage metadatum and every authored attribute of the default prims are equal."""
    a, b = Usd.Stage.Open(usd), Usd.Stage.Open(other)
    if b is None:
        fail(f"{other}: USD cannot open it")
    for key in ["defaultPrim", "timeCodesPerSecond", "framesPerSecond", "startTimeCode", "endTimeCode", "upAxis", "metersPerUnit"]:
        if a.GetMetadata(key) != b.GetMetadata(key):
            fail(f"stage {key}: {a.GetMetadata(key)} in {usd}, {b.GetMetadata(key)} in {other}")
    pa, pb = a.GetDefaultPrim(), b.GetDefaultPrim()
    if pa.GetTypeName() != pb.GetTypeName():
        fail(f"prim type {pa.GetTypeName()} vs {pb.GetTypeName()}")
    names = [x.GetName() for x in pa.GetAuthoredAttributes()]
    if names != [x.GetName() for x in pb.GetAuthoredAttributes()]:
        fail(f"attributes {names} vs {[x.GetName() for x in pb.GetAuthoredAttributes()]}")
    for name in names:
        x, y = pa.GetAttribute(name), pb.GetAttribute(name)
        described = []
        for key in ["typeName", "variability", "interpolation", "elementSize", "custom"]:
            if x.GetMetadata(key) != y.GetMetadata(key):
                fail(f"{name} {key}: {x.GetMetadata(key)} vs {y.GetMetadata(key)}")
            if x.HasAuthoredMetadata(key) and key != "custom":
                described.append(f"{key} {x.GetMetadata(key)}")
        times = x.GetTimeSamples()
        if times != y.GetTimeSamples():
            fail(f"{name}: time samples {times} vs {y.GetTimeSamples()}")
        for t in times or [Usd.TimeCode.Default()]:
            u, v = x.Get(t), y.Get(t)
            if (u is None) != (v is None) or (u is not None and not np.array_equal(np.array(u), np.array(v))):
                fail(f"{name} at {t}: the values differ")
        print(f"same: {name} ({', '.join(described)}; {len(times)} samples)")
    print(f"SAME: {len(names)} attributes of {usd} and {other}")


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("usd")
    parser.add_argument("ply_dir")
    parser.add_argument("--fps", type=float, default=24.0)
    parser.add_argument("--start", type=float, default=1.0)
    parser.add_argument("--up-axis", default="Y")
    parser.add_argument("--expect-color", action="store_true")
    parser.add_argument("--expect-st", action="store_true")
    parser.add_argument("--same-as")
    args = parser.parse_args()

    files = sorted(pathlib.Path(args.ply_dir).glob("frame_*.ply"))
    if not files:
        fail(f"{args.ply_dir}: no PLY frames")
    frames = [read_ply(f) for f in files]
    n = len(frames)

    stage = Usd.Stage.Open(args.usd)
    if stage is None:
        fail(f"{args.usd}: USD cannot open it")
    prim = stage.GetDefaultPrim()
    if not prim or not prim.IsA(UsdGeom.Mesh):
        fail(f"{args.usd}: the default prim is not a Mesh")
    mesh = UsdGeom.Mesh(prim)
    primvars = UsdGeom.PrimvarsAPI(prim)
    times = [args.start + k for k in range(n)]
    if stage.GetTimeCodesPerSecond() != args.fps:
        fail(f"timeCodesPerSecond {stage.GetTimeCodesPerSecond()} is not {args.fps}")
    if (stage.GetStartTimeCode(), stage.GetEndTimeCode()) != (times[0], times[-1]):
        fail(f"time codes {stage.GetStartTimeCode()}..{stage.GetEndTimeCode()} are not {times[0]}..{times[-1]}")

    if UsdGeom.GetStageUpAxis(stage) != args.up_axis:
        fail(f"upAxis {UsdGeom.GetStageUpAxis(stage)} is not {args.up_axis}")

    attributes = {
        "points": mesh.GetPointsAttr(),
        "faceVertexCounts": mesh.GetFaceVertexCountsAttr(),
        "faceVertexIndices": mesh.GetFaceVertexIndicesAttr(),
        "extent": mesh.GetExtentAttr(),
        "velocities": mesh.GetVelocitiesAttr(),
        "primvars:id": primvars.GetPrimvar("id").GetAttr(),
    }
    expected_primvars = ["id"]
    if args.expect_color:
        expected_primvars.append("displayColor")
    if args.expect_st:
        expected_primvars.append("st")
    for name in expected_primvars:
        primvar = primvars.GetPrimvar(name)
        if not primvar or primvar.GetInterpolation() != UsdGeom.Tokens.vertex:
            fail(f"primvar {name} is missing or not of vertex interpolation")
        attributes[f"primvars:{name}"] = primvar.GetAttr()
    for name, attribute in attributes.items():
        samples = attribute.GetTimeSamples()
        if samples != times:
            fail(f"{name}: time samples {samples[:3]}... ({len(samples)}) are not the {n} frames")

    expected_velocities = velocities_by_definition(frames, args.fps)
    worst = 0.0
    for k, ((vertices, faces), t) in enumerate(zip(frames, times)):
        where = f"frame {k} ({files[k].name}, time {t})"
        points = np.array(mesh.GetPointsAttr().Get(t), dtype=np.float32)
        counts = np.array(mesh.GetFaceVertexCountsAttr().Get(t))
        indices = np.array(mesh.GetFaceVertexIndicesAttr().Get(t))
        ids = np.array(primvars.GetPrimvar("id").Get(t))
        velocities = np.array(mesh.GetVelocitiesAttr().Get(t), dtype=np.float64)
        if len(points) != len(vertices) or len(counts) != len(faces):
            fail(f"{where}: {len(points)} points, {len(counts)} faces; the PLY frame has {len(vertices)}, {len(faces)}")
        if not np.all(counts == 3) or not np.array_equal(indices, faces.reshape(-1)):
            fail(f"{where}: the faces differ from the PLY frame's")
        ply_points = np.stack([vertices["x"], vertices["y"], vertices["z"]], 1)
        if not np.array_equal(points, ply_points):
            fail(f"{where}: the points differ from the PLY frame's")
        if not np.array_equal(ids.astype(np.int64), vertices["id"].astype(np.int64)):
            fail(f"{where}: the id primvar differs from the PLY ids")
        extent = np.array(mesh.GetExtentAttr().Get(t))
        if len(points) and not np.allclose(extent, [ply_points.min(0), ply_points.max(0)]):
            fail(f"{where}: extent {extent.tolist()} is not the points' box")
        expected = expected_velocities[k]
        error = np.linalg.norm(velocities - expected, axis=1)
        scale = np.linalg.norm(expected, axis=1)
        relative = np.where(scale > 0, error / np.where(scale > 0, scale, 1), error)
        if relative.size and relative.max() > 1e-5:
            i = int(relative.argmax())
            fail(f"{where}: vertex {i} (id {vertices['id'][i]}) velocity {velocities[i]} vs {expected[i]} by definition")
        worst = max(worst, float(relative.max()) if relative.size else 0.0)
        if {"vx", "vy", "vz"} <= set(vertices.dtype.names):
            ply_velocities = np.stack([vertices["vx"], vertices["vy"], vertices["vz"]], 1)
            if not np.array_equal(velocities.astype(np.float32), ply_velocities):
                fail(f"{where}: the velocities differ from the PLY frame's vx vy vz")
        channels = []
        if args.expect_color:
            colour = np.array(primvars.GetPrimvar("displayColor").Get(t), dtype=np.float32)
            ply = np.stack([vertices["red"], vertices["green"], vertices["blue"]], 1)
            if not np.array_equal(colour, ply):
                fail(f"{where}: displayColor differs from the PLY colours")
            channels.append("displayColor")
        if args.expect_st:
            st = np.array(primvars.GetPrimvar("st").Get(t), dtype=np.float32)
            if not np.array_equal(st, np.stack([vertices["u"], vertices["v"]], 1)):
                fail(f"{where}: st differs from the PLY u v")
            channels.append("st")
        moving = int((scale > 0).sum())
        print(
            f"{where}: {len(points)} points, {len(counts)} faces, ids equal, "
            f"{moving} moving vertices, max relative velocity error {relative.max() if relative.size else 0:.2e}"
            + (f", {' '.join(channels)} equal" if channels else "")
        )
    print(f"OK: {n} frames at {args.fps} fps from time code {times[0]}; worst relative velocity error {worst:.2e}")
    if args.same_as:
        same_as(args.usd, args.same_as)


if __name__ == "__main__":
    main()
