#include "fluidsimulation.h"
#include "vmath.h"
int main() {
    // A ball of liquid dropped into a shallow pool beside a column that collapses.
    int isize = 64, jsize = 48, ksize = 48;
    double dx = 0.125;
    FluidSimulation fluidsim(isize, jsize, ksize, dx);
    fluidsim.setSurfaceSubdivisionLevel(1);
    fluidsim.disableOpenCLParticleAdvection();
    fluidsim.disableOpenCLScalarField();
    fluidsim.setMeshOutputFormatAsPLY();
    fluidsim.disableAutosave();
    double w, h, d;
    fluidsim.getSimulationDimensions(&w, &h, &d);
    AABB pool; pool.position = vmath::vec3(0, 0, 0); pool.width = w; pool.height = 0.18 * h; pool.depth = d;
    fluidsim.addFluidCuboid(pool);
    AABB column; column.position = vmath::vec3(0, 0, 0); column.width = 0.2 * w; column.height = 0.7 * h; column.depth = 0.35 * d;
    fluidsim.addFluidCuboid(column);
    fluidsim.addImplicitFluidPoint(0.65 * w, 0.7 * h, 0.55 * d, 1.6);
    fluidsim.addBodyForce(0.0, -25.0, 0.0);
    fluidsim.initialize();
    double timestep = 1.0 / 30.0;
    for (int i = 0; i < 56; i++) {
        fluidsim.update(timestep);
    }
    return 0;
}
