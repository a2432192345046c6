"""Benchmark (not a test): impact's explicit FEM step against its peer, a scipy CSR loop.

The peer assembles the same plane-strain Q4 stiffness (scikit-fem, ElementQuad1, 2x2 Gauss)
and row-sum lumped mass on the plate-wave mesh at NX x NY elements, then times the same
central-difference step in numpy: u += dt v; f = K @ u (one CSR matvec); a = (f_ext - f)/m;
v += dt a. impact's step is timed by `impact run plate-wave --cells NX --method fem
--no-files --no-reference --t-end T` (the stepping wall time of summary.json over its
steps). Rounds are interleaved; medians and their ratio are printed. One thread each:
run with RAYON_NUM_THREADS=1 OMP_NUM_THREADS=1 (scipy's CSR matvec is single-threaded).

    RAYON_NUM_THREADS=1 OMP_NUM_THREADS=1 scripts/.venv/bin/python scripts/bench_fem_scipy.py
"""
import os
import sys
import time

import numpy as np
from bench_common import impact_run, interleaved, report
from skfem import Basis, BilinearForm, ElementQuad1, ElementVector, MeshQuad, asm
from skfem.models.elasticity import lame_parameters, linear_elasticity

E, NU, RHO = 2.0e11, 0.3, 7800.0
L, H = 4.0, 3.0
NX = int(os.environ.get("NX", "1000"))
NY = NX * 3 // 4
STEPS, ROUNDS = 30, 3


def assemble():
    xs, ys = np.linspace(0.0, L, NX + 1), np.linspace(0.0, H, NY + 1)
    x, y = np.meshgrid(xs, ys)
    p = np.vstack([x.ravel(), y.ravel()])
    i, j = np.meshgrid(np.arange(NX), np.arange(NY))
    v0 = (j * (NX + 1) + i).ravel()
    quads = np.vstack([v0, v0 + 1, v0 + NX + 2, v0 + NX + 1])
    mesh = MeshQuad(p, quads)
    basis = Basis(mesh, ElementVector(ElementQuad1()))
    lam, mu = lame_parameters(E, NU)
    stiffness = asm(linear_elasticity(lam, mu), basis).tocsr()

    @BilinearForm
    def mass(u, v, w):
        return RHO * (u[0] * v[0] + u[1] * v[1])

    lumped = np.asarray(asm(mass, basis).sum(axis=1)).ravel()
    return stiffness, lumped


def scipy_step_seconds(stiffness, lumped):
    n = lumped.size
    rng = np.random.default_rng(1)
    u, v = rng.standard_normal(n) * 1e-6, np.zeros(n)
    f_ext = np.zeros(n)
    dt = 1e-8
    times = []
    for _ in range(STEPS):
        start = time.perf_counter()
        u += dt * v
        f = stiffness @ u
        a = (f_ext - f) / lumped
        v += dt * a
        times.append(time.perf_counter() - start)
    return float(np.median(times))


def impact_step_ms():
    # about 30 steps: the stable step is 0.9 dx / c_L
    run = impact_run("plate-wave", NX, "fem", 30 * 0.9 * (L / NX) / 5875.0)
    return 1e3 * run["wall_s"] / run["steps"]


def main():
    stiffness, lumped = assemble()
    print(f"plate-wave {NX}x{NY}: {lumped.size} dofs, {stiffness.nnz} nonzeros", flush=True)
    peer, ours = interleaved(ROUNDS, lambda: 1e3 * scipy_step_seconds(stiffness, lumped), impact_step_ms)
    report("scipy CSR loop", peer, "impact fem", ours, "ms per step", 2, "the scipy loop")
    return 0


if __name__ == "__main__":
    sys.exit(main())
