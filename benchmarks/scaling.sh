#!/usr/bin/env bash
# Thread scaling of one method's step loop: `impact run` with RAYON_NUM_THREADS=1 and 2,
# alternated, REPS times each; prints the stepping wall time (summary.json `wall_s`, outputs
# excluded) of every run, then the best and median per thread count and their ratio.
# Usage: benchmarks/scaling.sh [scene] [cells] [method] [t_end] [reps]
set -euo pipefail
scene=${1:-plate}; cells=${2:-1000}; method=${3:-dgmpm}; t_end=${4:-2e-5}; reps=${5:-6}
exe=${IMPACT_BIN:-target/release/impact}
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
for r in $(seq "$reps"); do
  for th in 1 2; do
    RAYON_NUM_THREADS=$th "$exe" run "$scene" --cells "$cells" --method "$method" \
      --no-files --quiet --t-end "$t_end" --out "$out/run" > /dev/null
    python3 -c "import json,sys; d=json.load(open('$out/run/summary.json')); r=d['runs'][0]; print($th, r['steps'], r['cells'], r['wall_s'])" >> "$out/times"
  done
done
python3 - "$out/times" <<'PY'
import sys, statistics
rows = [l.split() for l in open(sys.argv[1])]
by = {}
for th, steps, cells, wall in rows:
    by.setdefault(int(th), []).append((float(wall), int(steps), int(cells)))
for th, runs in sorted(by.items()):
    walls = [w for w, _, _ in runs]
    steps, cells = runs[0][1], runs[0][2]
    print(f"threads {th}: wall_s {' '.join(f'{w:.3f}' for w in walls)}; best {min(walls):.3f} s "
          f"({steps * cells / min(walls) / 1e6:.2f} M updates/s), median {statistics.median(walls):.3f} s")
b1, b2 = min(w for w, _, _ in by[1]), min(w for w, _, _ in by[2])
m1, m2 = statistics.median(w for w, _, _ in by[1]), statistics.median(w for w, _, _ in by[2])
print(f"speed-up 2 threads / 1 thread: best {b1 / b2:.2f}x, median {m1 / m2:.2f}x")
PY
