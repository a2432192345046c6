"""03: a parameter study: DGMPM's error on the bar against Courant number and points
per cell.

The paper shows that DGMPM with one point per cell is exact at Courant 1 and smears the
front below it, and that more points per cell lower the stable Courant number. Here the
L1 error and the front width at the first output time are tabulated over Courant
numbers × points per cell, each run in-process with the GIL released (a thread pool
could run several at once).

Run: python examples/03_parameter_study.py [figure folder]
"""
import matplotlib.pyplot as plt

import impact
from _common import out_dir

courants = [0.25, 0.5, 0.75, 1.0]
points = [1, 2]
table = {}
for ppc in points:
    for c in courants:
        try:
            res = impact.run(
                "bar", methods=["dgmpm"], files=False, courant=c, points_per_cell=ppc,
                cells=100, output_times=[4e-4],
            )
            m = res.metrics[0]["times"][0]
            table[(ppc, c)] = (m["l1_rel"], m["front_width_cells"])
        except impact.SceneError as e:  # above the von Neumann limit: refused, as the CLI does
            table[(ppc, c)] = None
            print(f"ppc {ppc}, C {c}: refused ({str(e)[:70]}...)")

print(f"{'ppc':>3} " + " ".join(f"{'C ' + str(c):>18}" for c in courants))
for ppc in points:
    cells = []
    for c in courants:
        v = table[(ppc, c)]
        cells.append(f"{'refused':>18}" if v is None else f"{v[0]:>9.2e} {v[1]:>5.2f} cl")
    print(f"{ppc:>3} " + " ".join(cells))

fig, ax = plt.subplots(figsize=(9 / 2.54, 7 / 2.54), constrained_layout=True)
for ppc in points:
    xs = [c for c in courants if table[(ppc, c)] is not None]
    ax.semilogy(xs, [max(table[(ppc, c)][0], 1e-16) for c in xs], "o-", label=f"{ppc} ppc")
ax.set_xlabel("Courant number")
ax.set_ylabel("L1 relative error of σ_xx")
ax.set_title("DGMPM on the bar", fontsize=9)
ax.legend(fontsize=8)
path = out_dir() / "03_parameter_study.png"
fig.savefig(path, dpi=150)
print(f"wrote {path}")
