"""The gate's table in docs/cli.md: `impact check bar|plate` with DGMPM at Courant 0.5, 0.9, 1.0
and 1-4 points per cell (Euler; RK2 beside it at several points per cell), MPM at the scene's
configuration (Courant 0.5, 1 point per cell). Usage: python3 scripts/gate_table.py target/release/impact"""
import json, subprocess, sys, tempfile, os
exe = sys.argv[1]
rows = []
for scene, layouts in [("bar", [1, 2, 3, 4]), ("plate", [1, 4])]:
    for courant in [0.5, 0.9, 1.0]:
        for ppc in layouts:
            for integ in ["euler", "rk2"]:
                f = tempfile.mktemp(suffix=".json")
                cmd = [exe, "check", scene, "--dgmpm-courant", str(courant),
                       "--dgmpm-points-per-cell", str(ppc), "--integrator", integ,
                       "--quiet", "--json", f]
                p = subprocess.run(cmd, capture_output=True, text=True)
                if p.returncode == 2:
                    msg = p.stderr.strip().splitlines()[-1]
                    lim = msg.split("von Neumann limit ")[1].split(" ")[0] if "von Neumann limit" in msg else "?"
                    rows.append((scene, courant, ppc, integ, "-", "-", "-", "-", f"refused (von Neumann limit {lim})"))
                    continue
                d = json.load(open(f)); os.remove(f)
                r = d["reports"][0]
                w = lambda k: "/".join("-" if x[k] is None else f"{x[k]:.2f}" for x in r["rows"])
                rows.append((scene, courant, ppc, integ, w("dgmpm_front"), w("mpm_front"),
                             w("dgmpm_overshoot"), w("mpm_overshoot"),
                             "pass" if r["pass"] else "FAIL"))
                if integ == "euler" and ppc == 1:
                    break
print("| scene | DGMPM Courant | ppc | integrator | DGMPM width (cells) | MPM width | DGMPM overshoot % | MPM overshoot % | verdict |")
print("|---|---|---|---|---|---|---|---|---|")
for r in rows:
    print("| " + " | ".join(str(x) for x in r) + " |")
