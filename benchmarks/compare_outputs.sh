#!/usr/bin/env bash
# compare_outputs.sh BIN_A BIN_B LIST
# Bit-for-bit check of two `impact` binaries: for each line `NAME RUN-ARGS...` of LIST
# (benchmarks/compare/{dgmpm,mpm,fem}.txt), run `BIN run RUN-ARGS --no-reference --quiet
# --out DIR` with both binaries at RAYON_NUM_THREADS 1 and 2 and compare every output file
# with `cmp`, except the JSON files and scene.toml (they name the commit and the wall time).
# Prints each differing file and the count; exits 1 if any run failed or any file differed.
set -uo pipefail
a=$1; b=$2; list=$3
work=$(mktemp -d); trap 'rm -rf "$work"' EXIT
fail=0; compared=0
while read -r name args; do
  [ -z "$name" ] && continue
  for threads in 1 2; do
    rm -rf "$work/a" "$work/b"
    # shellcheck disable=SC2086
    RAYON_NUM_THREADS=$threads "$a" run $args --no-reference --quiet --out "$work/a" >/dev/null 2>&1 \
      || { echo "first binary failed: $name"; fail=1; continue; }
    # shellcheck disable=SC2086
    RAYON_NUM_THREADS=$threads "$b" run $args --no-reference --quiet --out "$work/b" >/dev/null 2>&1 \
      || { echo "second binary failed: $name"; fail=1; continue; }
    while read -r file; do
      compared=$((compared + 1))
      cmp -s "$work/a/$file" "$work/b/$file" || { echo "differs: $name, $threads threads, $file"; fail=1; }
    done < <(cd "$work/a" && find . -type f ! -name '*.json' ! -name scene.toml | sort)
  done
done < "$list"
echo "files compared: $compared"
exit "$fail"
