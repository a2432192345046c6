#!/usr/bin/env bash
# callgrind_per_update.sh BIN LABEL UNITS run-args...
# Instructions per update: callgrind totals of `BIN run <args> --no-files --no-reference --quiet
# --output-times T` at T = 1.7e-5 and 3.4e-5 s (one thread), difference divided by the extra
# steps (summary.json "steps") and by UNITS (cells or points).
set -euo pipefail
bin=$1; label=$2; units=$3; shift 3
dir=/tmp/cg_$label; rm -rf "$dir"; mkdir -p "$dir"
declare -a totals steps
i=0
for t in 1.7e-5 3.4e-5; do
  RAYON_NUM_THREADS=1 valgrind --tool=callgrind --callgrind-out-file="$dir/cg.$i.out" \
    "$bin" run "$@" --no-files --no-reference --quiet --output-times "$t" --out "$dir/run$i" \
    >"$dir/stdout.$i" 2>"$dir/vg.$i.log"
  totals[$i]=$(grep -E '^(summary|totals):' "$dir/cg.$i.out" | tail -1 | awk '{print $2}')
  steps[$i]=$(python3 -c "import json,sys;print(json.load(open('$dir/run$i/summary.json'))['runs'][0]['steps'])")
  i=$((i+1))
done
python3 - "${totals[0]}" "${totals[1]}" "${steps[0]}" "${steps[1]}" "$units" "$label" <<'PY'
import sys
t0,t1,s0,s1,u=map(float,sys.argv[1:6]); label=sys.argv[6]
print(f"{label}: totals {int(t0)} / {int(t1)}, steps {int(s0)} / {int(s1)}, per update {(t1-t0)/(s1-s0)/u:.1f}")
PY
