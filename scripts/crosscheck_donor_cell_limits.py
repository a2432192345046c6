"""Independent von Neumann limits of donor-cell finite volumes (Godunov's first-order
upwind, unsplit, forward Euler) for isotropic linear elasticity, the scheme DGMPM reduces
to at one point per cell (every node of a cell holds the point's value, and the point takes
the mean of the nodal rates: the volume terms cancel and the face fluxes remain). Written
from the scheme's definition, sharing nothing with `impact::von_neumann`: the 9 unknowns
(v, σ) of a cell, the exact Riemann solution at each face (normal impedance ρ c_p,
tangential ρ c_s), the 9 × 9 amplification matrix on a Fourier mode, numpy's eigenvalues,
bisection on the Courant number Δt c_p/Δx. ν = 0.3; units ρ = c_p = 1.

Prints 2D 0.65167 (θ_z = 0, 24² phases; `impact stability`: 0.6516) and 3D 0.48331
(16³ phases; tests/stability.rs pins the program's 0.4833). The tests (run by
scripts/test.sh) compare them with the limit the program's guard states when it refuses
donor-cell at Courant 0.99 on `plate-wave` and `block-wave` (ν = 0.3, square cells).

    scripts/.venv/bin/python scripts/crosscheck_donor_cell_limits.py
"""
import itertools
import re
import subprocess

import numpy as np
from conftest import impact_bin

POISSON = 0.3
MU = (1 - 2 * POISSON) / (2 * (1 - POISSON))  # μ/(λ + 2μ) with λ + 2μ = 1
LAM = 1 - 2 * MU
CS = np.sqrt(MU)


def hooke(eps):
    return LAM * np.trace(eps) * np.eye(3) + 2 * MU * eps


def unpack(q):
    v = q[:3]
    s = np.array([[q[3], q[8], q[7]], [q[8], q[4], q[6]], [q[7], q[6], q[5]]])
    return v, s


def pack(v, s):
    return np.array([*v, s[0, 0], s[1, 1], s[2, 2], s[1, 2], s[0, 2], s[0, 1]], dtype=complex)


def godunov(q_left, q_right, axis):
    """(v*, t*) of the exact Riemann solution on a face normal to `axis`."""
    n = np.zeros(3)
    n[axis] = 1
    v_l, s_l = unpack(q_left)
    v_r, s_r = unpack(q_right)
    t_l, t_r = s_l @ n, s_r @ n
    z = np.full(3, CS)
    z[axis] = 1.0
    v_star = (v_l + v_r) / 2 + (t_r - t_l) / (2 * z)
    t_star = (t_l + t_r) / 2 + z * (v_r - v_l) / 2
    return v_star, t_star


def rates(theta, dim):
    """dq/dt (Δx = 1) on the mode q e^{i k·θ}, as a 9 × 9 matrix."""
    m = np.zeros((9, 9), complex)
    for k in range(9):
        q = np.zeros(9, complex)
        q[k] = 1
        dv = np.zeros(3, complex)
        ds = np.zeros((3, 3), complex)
        for axis in range(dim):
            e = np.exp(1j * theta[axis])
            n = np.zeros(3)
            n[axis] = 1
            v_hi, t_hi = godunov(q, q * e, axis)
            v_lo, t_lo = godunov(q / e, q, axis)
            dv += t_hi - t_lo
            jump = v_hi - v_lo
            ds += hooke(0.5 * (np.outer(jump, n) + np.outer(n, jump)))
        m[:, k] = pack(dv, ds)
    return m


def rate_matrices(samples, dim):
    """The rate matrices of every phase of the grid (they do not depend on the Courant
    number, so they are built once and the bisection only forms `1 + C·M`)."""
    phases = 2 * np.pi * np.arange(samples) / samples
    return np.array([rates(list(theta) + [0.0] * (3 - dim), dim)
                     for theta in itertools.product(phases, repeat=dim)])


def max_radius(courant, matrices):
    g = np.eye(9) + courant * matrices
    return abs(np.linalg.eigvals(g)).max()


def limit(samples, dim):
    matrices = rate_matrices(samples, dim)
    lo, hi = 0.05, 1.0
    for _ in range(25):
        mid = (lo + hi) / 2
        if max_radius(mid, matrices) <= 1 + 1e-9:
            lo = mid
        else:
            hi = mid
    return lo


def program_limit(scene: str) -> float:
    """The von Neumann limit impact's guard states for donor-cell Euler at Courant 0.99."""
    run = subprocess.run([impact_bin(), "run", scene, "--method", "dgmpm", "--flux", "dcu",
                          "--courant", "0.99", "--quiet", "--no-files"],
                         capture_output=True, text=True)
    assert run.returncode == 2, f"{scene}: expected a refusal, got {run.returncode}: {run.stderr}"
    found = re.search(r"von Neumann limit ([0-9.]+)", run.stderr)
    assert found, run.stderr
    return float(found.group(1))


def test_2d_limit_equals_the_program_s():
    # the program bisects to 1e-5 and prints 4 decimals
    assert abs(limit(24, 2) - program_limit("plate-wave")) <= 2e-4


def test_3d_limit_equals_the_program_s():
    assert abs(limit(16, 3) - program_limit("block-wave")) <= 2e-4


if __name__ == "__main__":
    print(f"2D donor-cell Euler, 1 ppc: {limit(24, 2):.5f}")
    print(f"3D donor-cell Euler, 1 ppc: {limit(16, 3):.5f}")
