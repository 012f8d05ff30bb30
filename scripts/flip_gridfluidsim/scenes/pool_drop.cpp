// A ball of liquid dropped into a shallow pool beside a column that collapses.
#include "scene.h"

int main() {
    FluidSimulation sim(64, 48, 48, 0.125);
    prepare(sim, 1);
    sim.addFluidCuboid(box(sim, 0, 0, 0, 1, 0.18, 1));
    sim.addFluidCuboid(box(sim, 0, 0, 0, 0.2, 0.7, 0.35));
    double width, height, depth;
    sim.getSimulationDimensions(&width, &height, &depth);
    sim.addImplicitFluidPoint(0.65 * width, 0.7 * height, 0.55 * depth, 1.6);
    run(sim, 56);
    return 0;
}
