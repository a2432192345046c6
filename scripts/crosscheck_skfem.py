"""Cross-check of impact's explicit FEM on the paper's plate (§5.2) against scikit-fem.

scikit-fem assembles the plane-strain stiffness of bilinear quads (ElementQuad1, 2x2 Gauss)
and the row-sum lumped mass on the same 33x25 mesh; numpy runs the same central-difference
loop (half-step start, the controller's full stable steps with the last one shortened to
land on each output time) with the
same impact condition (v_x = 5 m/s on the left-edge nodes with y <= 1 m). Its sigma_xx at the
centres of the bottom-row elements and its nodal velocities must match impact's output to
1e-8 relative at every output time.
"""
import math

import meshio
import numpy as np
from conftest import read_csv
from skfem import Basis, BilinearForm, ElementQuad1, ElementVector, MeshQuad, asm
from skfem.helpers import dot
from skfem.models.elasticity import lame_parameters, linear_elasticity

E, NU, RHO = 2.0e11, 0.3, 7800.0
L, H, NX, NY = 4.0, 3.0, 33, 25
V_IMPACT, SEGMENT_TOP, COURANT = 5.0, 1.0, 0.9


def plate_mesh():
    xs = np.linspace(0.0, L, NX + 1)
    ys = np.linspace(0.0, H, NY + 1)
    x, y = np.meshgrid(xs, ys)  # vertex v = i + j (NX + 1), as in impact
    p = np.vstack([x.ravel(), y.ravel()])
    quads = []
    for j in range(NY):
        for i in range(NX):
            v0 = j * (NX + 1) + i
            quads.append([v0, v0 + 1, v0 + NX + 2, v0 + NX + 1])  # counter-clockwise
    return MeshQuad(p, np.array(quads).T)


def centre_stress_xx(u_x, u_y, lam, mu):
    """sigma_xx at the centres of the bottom-row elements from nodal displacements."""
    dx, dy = L / NX, H / NY
    i = np.arange(NX)
    v0, v1, v2, v3 = i, i + 1, i + NX + 2, i + NX + 1
    exx = ((u_x[v1] + u_x[v2]) - (u_x[v0] + u_x[v3])) / (2.0 * dx)
    eyy = ((u_y[v3] + u_y[v2]) - (u_y[v0] + u_y[v1])) / (2.0 * dy)
    return (lam + 2.0 * mu) * exx + lam * eyy


def test_fem_matches_scikit_fem(plate_out, plate_summary):
    lam, mu = lame_parameters(E, NU)  # plane strain: the 3D Lamé coefficients
    mesh = plate_mesh()
    basis = Basis(mesh, ElementVector(ElementQuad1()), intorder=2)
    stiffness = asm(linear_elasticity(lam, mu), basis).tocsr()

    @BilinearForm
    def mass(u, v, w):
        return RHO * dot(u, v)

    lumped = np.asarray(asm(mass, basis).sum(axis=1)).ravel()
    dof_x, dof_y = basis.nodal_dofs[0], basis.nodal_dofs[1]
    nodes_y = mesh.p[1]
    left = np.where((mesh.p[0] == 0.0) & (nodes_y <= SEGMENT_TOP + 1e-12))[0]
    constrained = dof_x[left]
    free = np.ones(basis.N)
    free[constrained] = 0.0

    c_p = math.sqrt((lam + 2.0 * mu) / RHO)
    dt_stable = COURANT * min(L / NX, H / NY) / c_p
    fem = next(r for r in plate_summary["runs"] if r["method"] == "fem")
    times = [t["t"] for t in fem["times"]]
    assert len(times) == 3

    u = np.zeros(basis.N)
    v_half = np.zeros(basis.N)
    acc = -(stiffness @ u) / lumped
    last_dt, t_now, steps = 0.0, 0.0, 0
    for k, t_out in enumerate(times):
        span = t_out - t_now
        n = max(1, math.ceil(span / dt_stable * (1.0 - 1e-12)))
        # full stable steps, the last one shortened to land on the output time
        for j in range(n):
            t0 = t_now + j * dt_stable
            t1 = t_out if j + 1 == n else t0 + dt_stable
            dt = t1 - t0
            v_half += acc * (0.5 * (last_dt + dt))
            v_half[constrained] = V_IMPACT
            u += dt * v_half
            acc = -(stiffness @ u) / lumped
            last_dt = dt
            steps += 1
        t_now = t_out
        velocity = v_half + 0.5 * last_dt * acc * free

        profile = read_csv(plate_out / f"fem_t{k}.csv")
        sxx = centre_stress_xx(u[dof_x], u[dof_y], lam, mu)
        scale = np.abs(sxx).max()
        assert scale > 1e7, "the wave must be in the plate"
        np.testing.assert_allclose(profile["cauchy_stress_xx"], sxx, rtol=0, atol=1e-8 * scale)

        grid = meshio.read(plate_out / f"fem_grid_t{k}.vtu")
        v_impact = grid.point_data["nodal_velocity"]
        v_scale = np.abs(velocity).max()
        np.testing.assert_allclose(v_impact[:, 0], velocity[dof_x], rtol=0, atol=1e-8 * v_scale)
        np.testing.assert_allclose(v_impact[:, 1], velocity[dof_y], rtol=0, atol=1e-8 * v_scale)
    assert steps == fem["steps"]
