"""Makes GridFluidSim3D (commit 5dbd0ca, 2017) build with a current g++ and OpenCL 2 headers, and
run on the CPU alone: usage `patch.py SOURCE_DIR`.

- the OpenCL C++ bindings the distributions ship now are `cl2.hpp`, where `cl::__local` is
  `cl::Local`: the sources and the build check take those;
- the OpenCL objects may fail to initialize (no OpenCL device): the simulation goes on with the
  CPU paths the scenes select, which must then return instead of falling through to the kernels;
- the log of the OpenCL device's properties is skipped (there may be none).
"""
import pathlib
import re
import sys

root = pathlib.Path(sys.argv[1])
src = root / "src"
BINDINGS = (
    "#define CL_HPP_MINIMUM_OPENCL_VERSION 110\n"
    "    #define CL_HPP_TARGET_OPENCL_VERSION 120\n"
    "    #define CL_HPP_ENABLE_PROGRAM_CONSTRUCTION_FROM_ARRAY_COMPATIBILITY\n"
    "    #define CL_HPP_ENABLE_SIZE_T_COMPATIBILITY\n"
    "    #define CL_HPP_CL_1_2_DEFAULT_BUILD\n"
    "    #include <CL/cl2.hpp>"
)


def edit(name, change, folder=src):
    path = folder / name
    text = path.read_text()
    new = change(text)
    if new == text:
        sys.exit(f"{path}: nothing to change (already patched, or another version)")
    path.write_text(new)


def cpu_paths(text):
    text = text.replace("    FLUIDSIM_ASSERT(_isInitialized);\n", "")
    text = text.replace("cl::__local", "cl::Local")
    return re.sub(
        r"(if \(!_isOpenCLEnabled\) \{\n(\s+)(_\w+NoCL\([^;]*\);))\n(\s+)\}",
        lambda m: f"{m.group(1)}\n{m.group(2)}return;\n{m.group(4)}}}",
        text,
    )


edit("CMakeLists.txt", lambda t: t.replace('/cl.hpp")', '/cl2.hpp")'), root)
for header in ("clscalarfield.h", "particleadvector.h"):
    edit(header, lambda t: t.replace("#include <CL/cl.hpp>", BINDINGS))
edit("clscalarfield.cpp", cpu_paths)
edit("particleadvector.cpp", cpu_paths)
edit(
    "fluidsimulation.cpp",
    lambda t: t.replace(
        "    bool success = _particleAdvector.initialize();\n    FLUIDSIM_ASSERT(success);\n\n"
        "    success = _scalarFieldAccelerator.initialize();\n    FLUIDSIM_ASSERT(success);",
        "    _particleAdvector.initialize();\n    _scalarFieldAccelerator.initialize();",
    ).replace("    _logOpenCLInfo();\n\n", ""),
)
