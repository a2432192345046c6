"""02: a 2D plate: colour maps of σ_xx per method.

The plane wave in a plate (`plate-wave`): a velocity step on the left edge of a 4 m × 3 m
plate sends a plane P wave to the right; its exact solution is the 1D one. Each method's
σ_xx averaged per grid cell (`Frame.map`, the CLI's stress_map.png) is drawn at the last
output time. A coarse grid keeps it quick.

Run: python examples/02_plate.py [figure folder]
"""
import matplotlib.pyplot as plt
import numpy as np

import impact
from _common import out_dir

scene = impact.Scene.load("plate-wave").with_overrides(cells=48)
nx, ny = scene.to_dict()["domain"]["cells"]
result = impact.run(scene, files=False)

fig, axes = plt.subplots(1, 3, figsize=(19 / 2.54, 5 / 2.54), constrained_layout=True)
last = {m.method: m.frames[-1] for m in result}
limit = max(np.nanmax(np.abs(f.map)) for f in last.values())
for ax, (name, frame) in zip(axes, last.items()):
    image = ax.imshow(
        frame.map.reshape(ny, nx), origin="lower", cmap="RdBu_r", vmin=-limit, vmax=limit,
        extent=[0, 4, 0, 3],
    )
    ax.set_title(f"{name.upper()}, t = {frame.t * 1e3:.2f} ms", fontsize=8)
    ax.set_xlabel("x (m)", fontsize=8)
axes[0].set_ylabel("y (m)", fontsize=8)
fig.colorbar(image, ax=axes, label="σ_xx (Pa)", shrink=0.8)
path = out_dir() / "02_plate.png"
fig.savefig(path, dpi=150)
for record in result.metrics:
    m = record["times"][-1]
    print(f"{record['method']:<6} L1_rel {m['l1_rel']:.3e}  front {m['front_width_cells']:.2f} cells")
print(f"wrote {path}")
