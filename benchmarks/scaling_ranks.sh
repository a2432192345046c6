#!/usr/bin/env bash
# Strong scaling over MPI ranks × threads (issue 27): a method (METHOD=dgmpm, the default,
# mpm or fem) on the plate at 600×450 cells
# (`--cells 600`) run as 1 and 2 ranks × 1 and 2 threads, the four configurations
# interleaved, REPS rounds; prints every run's stepping wall time (summary.json `wall_s`:
# rank 0's clock, outputs excluded) and bytes exchanged per step, then the median per
# configuration, its speed-up over 1 × 1 and its parallel efficiency (speed-up / cores
# used). Needs a binary built with `--features mpi` and `mpirun`.
# Usage: [METHOD=mpm] benchmarks/scaling_ranks.sh [reps] [cells] [t_end]
set -euo pipefail
reps=${1:-3}; cells=${2:-600}; t_end=${3:-}
exe=${IMPACT_BIN:-target/release/impact}
method=${METHOD:-dgmpm}
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
mpi=(mpirun --oversubscribe --allow-run-as-root)
extra=()
[ -z "$t_end" ] || extra=(--t-end "$t_end")
for r in $(seq "$reps"); do
  for ranks in 1 2; do
    for threads in 1 2; do
      launch=()
      [ "$ranks" = 1 ] || launch=("${mpi[@]}" -np "$ranks")
      RAYON_NUM_THREADS=$threads "${launch[@]}" "$exe" run plate --cells "$cells" --method "$method" \
        --no-reference --no-files --quiet "${extra[@]}" --out "$out/run" >/dev/null
      python3 -c "import json; r=json.load(open('$out/run/summary.json'))['runs'][0]; \
print($ranks, $threads, r['steps'], r['cells'], r['wall_s'], r.get('ranks', 1), r.get('bytes_per_step', 0))" \
        >>"$out/times"
    done
  done
done
python3 - "$out/times" <<'PY'
import statistics, sys
rows = [l.split() for l in open(sys.argv[1])]
by = {}
for ranks, threads, steps, cells, wall, seen, sent in rows:
    assert int(seen) == int(ranks), f"asked for {ranks} ranks, ran on {seen}: a binary without mpi?"
    by.setdefault((int(ranks), int(threads)), []).append((float(wall), int(steps), int(cells), int(sent)))
base = statistics.median(w for w, *_ in by[(1, 1)])
print("ranks x threads | wall_s per round | median | speed-up | efficiency | bytes/step")
for (ranks, threads), runs in sorted(by.items()):
    walls = [w for w, *_ in runs]
    median = statistics.median(walls)
    speed = base / median
    print(f"{ranks} x {threads} | {', '.join(f'{w:.2f}' for w in walls)} | {median:.2f} | "
          f"{speed:.2f} | {speed / (ranks * threads):.0%} | {runs[0][3]}")
print(f"({runs[0][1]} steps of {runs[0][2]} cells)")
PY
