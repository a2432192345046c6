#!/usr/bin/env python3
"""interleaved_times.py ROUNDS LABEL=BIN:UNITS:ARGS ... : interleaved one-thread runs; ns per update =
wall_s / (steps * units) from summary.json; units given as LABEL=BIN:UNITS:ARGS"""
import json, os, subprocess, sys, statistics, tempfile
rounds = int(sys.argv[1])
specs = []
for spec in sys.argv[2:]:
    label, rest = spec.split("=", 1)
    binary, units, args = rest.split(":", 2)
    specs.append((label, binary, int(units), args.split()))
times = {label: [] for label, *_ in specs}
loads = []
env = dict(os.environ, RAYON_NUM_THREADS="1")
for r in range(rounds):
    loads.append(open("/proc/loadavg").read().split()[0])
    for label, binary, units, args in specs:
        with tempfile.TemporaryDirectory() as out:
            subprocess.run([binary, "run", *args, "--no-files", "--no-reference", "--quiet", "--out", out],
                           env=env, check=True, stdout=subprocess.DEVNULL)
            run = json.load(open(f"{out}/summary.json"))["runs"][0]
            times[label].append(run["wall_s"] / (run["steps"] * units) * 1e9)
print("load averages before each round:", ", ".join(loads))
for label, values in times.items():
    print(f"{label}: " + ", ".join(f"{v:.1f}" for v in values) + f"; median {statistics.median(values):.1f}")
