#include "fluidsimulation.h"
#include "vmath.h"
int main() {
    // Two columns collapsing towards each other across a shallow pool, meshed at half a cell.
    int isize = 64, jsize = 40, ksize = 40;
    double dx = 0.125;
    FluidSimulation fluidsim(isize, jsize, ksize, dx);
    fluidsim.setSurfaceSubdivisionLevel(2);
    fluidsim.setMinPolyhedronTriangleCount(0);
    fluidsim.disableOpenCLParticleAdvection();
    fluidsim.disableOpenCLScalarField();
    fluidsim.setMeshOutputFormatAsPLY();
    fluidsim.disableAutosave();
    double w, h, d;
    fluidsim.getSimulationDimensions(&w, &h, &d);
    AABB pool; pool.position = vmath::vec3(0, 0, 0); pool.width = w; pool.height = 0.12 * h; pool.depth = d;
    fluidsim.addFluidCuboid(pool);
    AABB left; left.position = vmath::vec3(0, 0, 0); left.width = 0.2 * w; left.height = 0.8 * h; left.depth = 0.5 * d;
    fluidsim.addFluidCuboid(left);
    AABB right; right.position = vmath::vec3(0.8 * w, 0, 0.5 * d); right.width = 0.2 * w; right.height = 0.6 * h; right.depth = 0.5 * d;
    fluidsim.addFluidCuboid(right);
    fluidsim.addBodyForce(0.0, -25.0, 0.0);
    fluidsim.initialize();
    double timestep = 1.0 / 30.0;
    for (int i = 0; i < 50; i++) {
        fluidsim.update(timestep);
    }
    return 0;
}
