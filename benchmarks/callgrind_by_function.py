#!/usr/bin/env python3
# callgrind_by_function.py LABEL UNITS_STEPS : per function, the difference of the two runs of
# callgrind_per_update.sh (in /tmp/cg_LABEL) divided by UNITS_STEPS (units x extra steps)
import subprocess, sys, re
out = {}
for i in (0, 1):
    txt = subprocess.run(["callgrind_annotate", "--threshold=100", f"/tmp/cg_{sys.argv[1]}/cg.{i}.out"], capture_output=True, text=True).stdout
    for line in txt.splitlines():
        m = re.match(r"\s*([\d,]+) \([\s\d.]+%\)\s+\S*?:(.*) \[", line)
        if m:
            name = re.sub(r"'\d+", "", m.group(2))
            out.setdefault(name, [0, 0])[i] += int(m.group(1).replace(",", ""))
u = float(sys.argv[2])
for k, v in sorted(out.items(), key=lambda kv: -(kv[1][1] - kv[1][0]))[:15]:
    print(f"{(v[1]-v[0])/u:9.1f}  {k[:120]}")
