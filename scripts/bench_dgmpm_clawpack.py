"""Benchmark (not a test): impact's DGMPM step against Clawpack's Fortran on the same plate.

Clawpack's peer is PyClaw's classic 2D solver with the Fortran Riemann solvers
`vc_elasticity_2D` (rpn2, rpt2), first order, `transverse_waves = 2`: the CTU scheme that
impact's DGMPM at one point per cell with forward Euler equals (scripts/crosscheck_clawpack.py
checks the fields to 1e-12). Both run the 4 m x 3 m steel plate at NX x NY cells, Courant 1,
a velocity impact on the left edge (Clawpack: a wall-type ghost of the impact velocity on
the left, extrapolation elsewhere; the edges cost nothing next to the interior). Clawpack's
time is `claw.run()` over STEPS fixed steps divided by the steps; impact's is `impact run
plate --cells NX --method dgmpm --no-files --no-reference` (the stepping wall time of
summary.json over its steps). Rounds are interleaved; medians and their ratio are printed,
in ns per cell-update. One thread each:

    RAYON_NUM_THREADS=1 OMP_NUM_THREADS=1 <venv with clawpack>/bin/python scripts/bench_dgmpm_clawpack.py
"""
import os
import sys
import time

import numpy as np
from bench_common import impact_run, interleaved, report
from clawpack import pyclaw, riemann

E, NU, RHO = 2.0e11, 0.3, 7800.0
LAMBDA = E * NU / ((1 + NU) * (1 - 2 * NU))
MU = E / (2 * (1 + NU))
CP = np.sqrt((LAMBDA + 2 * MU) / RHO)
CS = np.sqrt(MU / RHO)
L, H = 4.0, 3.0
NX = int(os.environ.get("NX", "1000"))
NY = round(NX * H / L)
STEPS, ROUNDS = 20, 3


def clawpack_ns_per_update():
    solver = pyclaw.ClawSolver2D(riemann.vc_elasticity_2D)
    solver.order = 1
    solver.transverse_waves = 2
    solver.dimensional_split = False
    solver.cfl_max = 1.1
    solver.cfl_desired = 1.0
    dx, dy = L / NX, H / NY
    dt = min(dx, dy) / CP
    solver.dt_variable = False
    solver.dt_initial = dt
    solver.max_steps = 10 * STEPS
    solver.bc_lower = [pyclaw.BC.wall, pyclaw.BC.extrap]
    solver.bc_upper = [pyclaw.BC.extrap, pyclaw.BC.extrap]
    solver.aux_bc_lower = [pyclaw.BC.extrap, pyclaw.BC.extrap]
    solver.aux_bc_upper = [pyclaw.BC.extrap, pyclaw.BC.extrap]
    domain = pyclaw.Domain([pyclaw.Dimension(0.0, L, NX, name="x"), pyclaw.Dimension(0.0, H, NY, name="y")])
    state = pyclaw.State(domain, solver.num_eqn, num_aux=5)
    state.aux[0], state.aux[1], state.aux[2] = RHO, LAMBDA, MU
    state.aux[3], state.aux[4] = CP, CS
    state.q[...] = 0.0
    state.q[3, :2, :] = 5.0  # the impact's velocity near the left edge
    claw = pyclaw.Controller()
    claw.solution = pyclaw.Solution(state, domain)
    claw.solver = solver
    claw.tfinal = STEPS * dt * (1 - 1e-9)
    claw.num_output_times = 1
    claw.output_format = None
    claw.verbosity = 0
    start = time.perf_counter()
    claw.run()
    seconds = time.perf_counter() - start
    return seconds / (STEPS * NX * NY) * 1e9


def impact_ns_per_update():
    run = impact_run("plate", NX, "dgmpm", STEPS * (L / NX) / CP)
    return run["wall_s"] / (run["steps"] * run["cells"]) * 1e9


def main():
    peer, ours = interleaved(ROUNDS, clawpack_ns_per_update, impact_ns_per_update)
    print(f"plate {NX}x{NY}, Courant 1, CTU, one thread")
    report("clawpack (Fortran rpn2/rpt2)", peer, "impact dgmpm", ours, "ns per cell-update", 1, "Clawpack")
    return 0


if __name__ == "__main__":
    sys.exit(main())
