// What every scene shares: the solver on the CPU alone, PLY frames, no autosave; gravity of
// 25 m/s² along -y; `frames` frames of 1/30 s. A scene adds its liquid between `prepare` and `run`.
// `SUBDIVISION` in the environment overrides the scene's surface subdivision level: pool_drop at
// 3 gives frames of 82k-117k vertices from the same simulation.
#include <cstdlib>
#include "fluidsimulation.h"
#include "vmath.h"

inline void prepare(FluidSimulation &sim, int subdivision) {
    const char *level = std::getenv("SUBDIVISION");
    sim.setSurfaceSubdivisionLevel(level ? std::atoi(level) : subdivision);
    sim.disableOpenCLParticleAdvection();
    sim.disableOpenCLScalarField();
    sim.setMeshOutputFormatAsPLY();
    sim.disableAutosave();
}

// A box from its corner and size, as fractions of the domain's width, height and depth.
inline AABB box(FluidSimulation &sim, double x, double y, double z, double w, double h, double d) {
    double width, height, depth;
    sim.getSimulationDimensions(&width, &height, &depth);
    AABB b;
    b.position = vmath::vec3(x * width, y * height, z * depth);
    b.width = w * width;
    b.height = h * height;
    b.depth = d * depth;
    return b;
}

inline void run(FluidSimulation &sim, int frames) {
    sim.addBodyForce(0.0, -25.0, 0.0);
    sim.initialize();
    for (int i = 0; i < frames; i++) {
        sim.update(1.0 / 30.0);
    }
}
