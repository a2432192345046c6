"""04: a scene of your own, from a dict.

An aluminium bar 2 m long, loaded at its left end by a velocity step of 10 m/s and fixed
at its right end: the wave reflects from the fixed end doubled in stress. The dict has
the keys of a scene file (docs/scenes.md); it is validated by the same code, so a wrong
field raises `impact.SceneError` naming the field, the value and what is allowed.

Run: python examples/04_custom_scene.py [figure folder]
"""
import matplotlib.pyplot as plt

import impact
from _common import out_dir

# start from a shipped scene's dict: every field written out, change what differs
scene = impact.Scene.load("bar").to_dict()
scene["name"] = "aluminium-bar"
scene["domain"]["length"] = [2.0]
scene["domain"]["cells"] = [100]
scene["material"].update(young=70e9, poisson=0.33, density=2700.0)
scene["boundary"]["left"] = {"kind": "velocity", "value": 10.0}
scene["boundary"]["right"] = {"kind": "velocity", "value": 0.0}  # a fixed end

try:
    impact.Scene.from_dict({**scene, "material": {**scene["material"], "density": -1.0}})
except impact.SceneError as e:
    print(f"a bad density is refused: {e}")

custom = impact.Scene.from_dict(scene)
result = impact.run(custom, methods=["dgmpm", "fem"], files=False)
print(f"reference: {result.reference}")

fig, ax = plt.subplots(figsize=(9 / 2.54, 7 / 2.54), constrained_layout=True)
for method in result:
    f = method.frames[-1]
    ax.plot(f.reference_position[:, 0], f.velocity[:, 0], ".", label=method.method.upper())
f = result["dgmpm"].frames[-1]
if f.reference_velocity_x is not None:
    ax.plot(f.reference_position[:, 0], f.reference_velocity_x, "k-", lw=0.8, label="exact")
ax.set_xlabel("x (m)")
ax.set_ylabel("v_x (m/s)")
ax.set_title(f"{custom.name}, t = {f.t * 1e3:.3f} ms", fontsize=9)
ax.legend(fontsize=8)
path = out_dir() / "04_custom_scene.png"
fig.savefig(path, dpi=150)
print(f"wrote {path}")
