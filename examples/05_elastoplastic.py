"""05: elastoplastic fronts: the elastic precursor and the plastic wave.

The J2 bar (`ep-bar`): a pressure above the yield stress splits the wave into a fast
elastic precursor at the yield stress and a slower plastic front; behind it the points
carry an equivalent plastic strain. The figure shows σ_xx and the plastic strain along
the bar for each method at the last output time, against the exact solution.

Run: python examples/05_elastoplastic.py [figure folder]
"""
import matplotlib.pyplot as plt

import impact
from _common import out_dir

result = impact.run("ep-bar", files=False, cells=200)
print(f"reference: {result.reference}")
fig, (top, bottom) = plt.subplots(2, 1, sharex=True, figsize=(9 / 2.54, 10 / 2.54),
                                  constrained_layout=True)
for method in result:
    f = method.frames[-1]
    x = f.reference_position[:, 0]
    top.plot(x, f.stress[:, 0, 0] / 1e6, ".", ms=2, label=method.method.upper())
    if f.plastic_strain is not None:
        bottom.plot(x, f.plastic_strain * 1e3, ".", ms=2, label=method.method.upper())
    m = method.metrics["times"][-1]
    print(f"{method.method:<6} front {m['front_width_cells']:.2f} cells, L1_rel {m['l1_rel']:.3e}")
f = result["dgmpm"].frames[-1]
if f.reference_stress_xx is not None:
    top.plot(f.reference_position[:, 0], f.reference_stress_xx / 1e6, "k-", lw=0.8, label="exact")
top.set_ylabel("σ_xx (MPa)")
bottom.set_ylabel("ε̄_p (10⁻³)")
bottom.set_xlabel("x (m)")
top.legend(fontsize=7)
top.set_title(f"ep-bar, t = {f.t * 1e3:.3f} ms", fontsize=9)
path = out_dir() / "05_elastoplastic.png"
fig.savefig(path, dpi=150)
print(f"wrote {path}")
