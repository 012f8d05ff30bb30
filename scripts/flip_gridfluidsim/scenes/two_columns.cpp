// Two columns collapsing towards each other across a shallow pool, meshed at half a cell.
#include "scene.h"

int main() {
    FluidSimulation sim(64, 40, 40, 0.125);
    prepare(sim, 2);
    sim.setMinPolyhedronTriangleCount(0);
    sim.addFluidCuboid(box(sim, 0, 0, 0, 1, 0.12, 1));
    sim.addFluidCuboid(box(sim, 0, 0, 0, 0.2, 0.8, 0.5));
    sim.addFluidCuboid(box(sim, 0.8, 0, 0.5, 0.2, 0.6, 0.5));
    run(sim, 50);
    return 0;
}
