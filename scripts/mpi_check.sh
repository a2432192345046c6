#!/usr/bin/env bash
# The MPI checks (issue 27), run by scripts/test.sh after `cargo build --release --features mpi`:
# DGMPM, MPM and FEM on bar and plate under `mpirun -np N`, N = 1..4, write the same fields
# as the serial run (profiles, grid VTK files and the metrics of summary.json byte for byte,
# and on one rank the samples' VTK files; on N > 1 ranks the grid in one piece per rank
# whose cells (FEM's: with their deformed corners and nodal velocity) are the serial grid's
# bit for bit, scripts/grid_pieces_check.py, and
# one samples piece per rank per frame, listed
# by a .pvtu that the .pvd lists: their arrays are compared with the serial file's by
# scripts/crosscheck_pvtu.py; the relative energy error, of sums per rank then in rank
# order, to 1e-12); MPM's updated frame on 1-3 ranks likewise (CPDI there on 2); a bad
# input, a blow-up and a folder that one rank cannot write stop every rank with one message and a
# non-zero exit. Boxes (--ranks-grid): DGMPM on the 2 x 2 plate and the 2 x 2 x 1 block,
# DGMPM, MPM (both frames: the moving plate in the updated one) and FEM on the 2 x 2 plate,
# byte for byte.
# Usage: scripts/mpi_check.sh [path/to/impact]
set -euo pipefail
cd "$(dirname "$0")/.."
bin="${1:-target/release/impact}"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
mpi=(timeout 300 mpirun --oversubscribe --allow-run-as-root)
fail() {
  echo "mpi: $*" >&2
  exit 1
}

for method in dgmpm mpm fem; do for scene in bar plate; do
  serial="$work/$method-$scene-serial"
  RAYON_NUM_THREADS=1 "$bin" run "$scene" --method "$method" --quiet --out "$serial" >/dev/null
  for n in 1 2 3 4; do
    out="$work/$method-$scene-np$n"
    RAYON_NUM_THREADS=1 "${mpi[@]}" -np "$n" "$bin" run "$scene" --method "$method" --quiet --out "$out" \
      >"$out.log" 2>&1 || fail "$method $scene on $n ranks failed: $(tail -5 "$out.log")"
    count=0
    samples=("$serial/${method}"_t*.vtu)
    [ "$n" = 1 ] || samples=()
    grids=("$serial/${method}"_grid_t*.vtu)
    if [ "$n" -gt 1 ]; then
      # the grid in pieces: every cell the serial one, bit for bit
      grids=()
      python3 scripts/grid_pieces_check.py "$serial" "$out" "$method" "$n" >/dev/null ||
        fail "$method $scene on $n ranks: the grid pieces differ from the serial grid files"
    fi
    for f in "$serial"/*.csv "${samples[@]}" "${grids[@]}"; do
      [ -f "$f" ] || continue
      cmp -s "$f" "$out/$(basename "$f")" || fail "$method $scene on $n ranks: $(basename "$f") differs from the serial run"
      count=$((count + 1))
    done
    if [ "$n" -gt 1 ]; then
      # one piece per rank per frame, a .pvtu per frame, listed by the .pvd
      for f in "$serial"/${method}_t*.vtu "$serial"/${method}_initial.vtu; do
        frame=$(basename "$f" .vtu)
        [ ! -e "$out/$frame.vtu" ] || fail "$method $scene on $n ranks: $frame.vtu written whole"
        grep -q "file=\"$frame.pvtu\"" "$out/${method}.pvd" || fail "$method $scene on $n ranks: ${method}.pvd lacks $frame.pvtu"
        for ((r = 0; r < n; r++)); do
          [ -s "$out/${frame}_r$r.vtu" ] || fail "$method $scene on $n ranks: no piece ${frame}_r$r.vtu"
          grep -q "Source=\"${frame}_r$r.vtu\"" "$out/$frame.pvtu" || fail "$method $scene on $n ranks: $frame.pvtu lacks rank $r"
        done
        [ ! -e "$out/${frame}_r$n.vtu" ] || fail "$method $scene on $n ranks: a piece of a rank that does not exist"
      done
      grep -q "${frame}_r$((n - 1)).vtu" "$out/manifest.json" || fail "$method $scene on $n ranks: the manifest lacks the last rank's piece"
    fi
    [ "$count" -gt 2 ] || fail "$method $scene: only $count field files compared"
    python3 - "$serial/summary.json" "$out/summary.json" "$n" "$method" <<'PY' || fail "$method $scene on $n ranks: summary.json"
import json, sys
a, b, n, method = json.load(open(sys.argv[1])), json.load(open(sys.argv[2])), int(sys.argv[3]), sys.argv[4]
ra, rb = a["runs"][0], b["runs"][0]
assert rb.get("ranks", 1) == n and (n == 1 or "slabs" in rb["decomposition"]), rb.get("decomposition")
assert ra["steps"] == rb["steps"] and ra["cells"] == rb["cells"]
# the halo: one layer each way per neighbour pair, 8 B per value; DGMPM and MPM (hats, USL):
# points (x, v, sigma: 2 + 2 + 4 values in 2D, 1 + 1 + 1 in 1D), 1 per layer on the bar,
# 33 on the plate; FEM: nodes (u, v, a: 3 x dim values), 1 per layer on the bar, 34 on the plate
if n > 1:
    if method == "fem":
        per_layer, values = {1: (1, 3), 2: (34, 6)}[a["dim"]]
    else:
        per_layer, values = {1: (1, 3), 2: (33, 8)}[a["dim"]]
    assert rb["bytes_per_step"] == 2 * (n - 1) * per_layer * values * 8, rb["bytes_per_step"]
else:
    assert "bytes_per_step" not in rb
for ta, tb in zip(ra["times"], rb["times"], strict=True):
    for k, va in ta.items():
        vb = tb[k]
        if k.startswith("energy"):  # (a relative error) of sums in rank order: round-off
            assert abs(va - vb) <= 1e-12, (k, va, vb)
        else:
            assert va == vb, (k, va, vb)
PY
  done
  echo "mpi: $scene ($method) on 1-4 ranks: fields equal to the serial run bit for bit, one piece per rank"
done; done

# same_as_serial LABEL SERIAL OUT METHOD RANKS: OUT's profiles are SERIAL's byte for byte, and
# its grid files too on one rank or, on several, the pieces' cells the serial grid files'
# bit for bit (scripts/grid_pieces_check.py; at least three files compared), and its metrics
# equal (the energies to 1e-12: sums in rank order), step count included
same_as_serial() {
  local label=$1 serial=$2 out=$3 method=$4 ranks=$5 count=0 f
  local grids=("$serial/${method}"_grid_t*.vtu)
  if [ "$ranks" -gt 1 ]; then
    # the grid in pieces
    grids=()
    python3 scripts/grid_pieces_check.py "$serial" "$out" "$method" "$ranks" >/dev/null ||
      fail "$label: the grid pieces differ from the serial grid files"
  fi
  for f in "$serial"/*.csv "${grids[@]}"; do
    [ -f "$f" ] || continue
    cmp -s "$f" "$out/$(basename "$f")" || fail "$label: $(basename "$f") differs from the serial run"
    count=$((count + 1))
  done
  [ "$count" -gt 2 ] || fail "$label: only $count field files compared"
  python3 - "$serial/summary.json" "$out/summary.json" <<'PY' || fail "$label: summary.json"
import json, sys
a, b = (json.load(open(p))["runs"][0] for p in sys.argv[1:3])
assert a["steps"] == b["steps"] and a["cells"] == b["cells"]
for ta, tb in zip(a["times"], b["times"], strict=True):
    for k, va in ta.items():
        assert abs(va - tb[k]) <= 1e-12 if k.startswith("energy") else va == tb[k], (k, va, tb[k])
PY
}

# MPM in the updated Lagrangian frame, points migrating between the slabs: an
# elastic-plastic plate impacted on its left edge while moving up (the cut axis) at 250-450
# m/s and right at 20-320 m/s (MUSL), so every point crosses one or two cell faces, rank
# faces too (on boxes along both axes); the profiles, the grid
# files and the metrics equal the serial run's byte for byte on 1-3 ranks (the energies to
# 1e-12: sums in rank order)
cat >"$work/moving.toml" <<'TOML'
name = "moving-plate"
dim = 2
[domain]
length = [4.0, 3.0]
cells = [33, 25]
points_per_cell = 1
[material]
model = "j2"
young = 2.0e11
poisson = 0.3
density = 7800.0
yield_stress = 4.0e8
hardening = 2.0e10
[boundary]
left = { kind = "normal-velocity", value = 20.0, from = 0.0, to = 1.0 }
right = { kind = "free" }
bottom = { kind = "free" }
top = { kind = "free" }
[initial]
velocity = ["20 + 100*y", "250 + 50*x"]
[time]
output_transits = [10, 20, 29]
[mpm]
courant = 0.5
frame = "updated-lagrangian"
stress_update = "musl"
TOML
serial="$work/ul-serial"
RAYON_NUM_THREADS=1 "$bin" run "$work/moving.toml" --method mpm --quiet --out "$serial" >/dev/null
for n in 1 2 3; do
  out="$work/ul-np$n"
  RAYON_NUM_THREADS=1 "${mpi[@]}" -np "$n" "$bin" run "$work/moving.toml" --method mpm --quiet --out "$out" \
    >"$out.log" 2>&1 || fail "mpm moving plate (updated frame) on $n ranks failed: $(tail -5 "$out.log")"
  same_as_serial "mpm moving plate (updated frame) on $n ranks" "$serial" "$out" mpm "$n"
done
echo "mpi: a moving plate (mpm, updated frame, points migrating) on 1-3 ranks: the serial run's files"
# the moving plate on 2 x 2 boxes (--ranks-grid 2,2): points migrate across the cuts
# between the lower and the upper boxes and between the left and the right ones, some
# through the boxes' corners; the serial run's files byte for byte
out="$work/ul-boxes-np4"
RAYON_NUM_THREADS=1 "${mpi[@]}" -np 4 "$bin" run "$work/moving.toml" --method mpm --ranks-grid 2,2 --quiet \
  --out "$out" >"$out.log" 2>&1 || fail "mpm moving plate (updated frame) on boxes 2,2 failed: $(tail -5 "$out.log")"
same_as_serial "mpm moving plate (updated frame) on boxes 2,2" "$serial" "$out" mpm 4
echo "mpi: a moving plate (mpm, updated frame, points migrating) on 4 ranks as boxes 2,2: the serial run's files"
# CPDI in the updated frame: the moving plate's domains deform with it and cross the cut
# with their points (a halo of 8 cells under MUSL); 2 ranks write the serial run's files
serial="$work/ul-cpdi-serial"
RAYON_NUM_THREADS=1 "$bin" run "$work/moving.toml" --method mpm --shape cpdi --quiet --out "$serial" >/dev/null
out="$work/ul-cpdi-np2"
RAYON_NUM_THREADS=1 "${mpi[@]}" -np 2 "$bin" run "$work/moving.toml" --method mpm --shape cpdi --quiet \
  --out "$out" >"$out.log" 2>&1 || fail "mpm moving plate (updated frame, CPDI) on 2 ranks failed: $(tail -5 "$out.log")"
same_as_serial "mpm moving plate (updated frame, CPDI) on 2 ranks" "$serial" "$out" mpm 2
echo "mpi: a moving plate (mpm, updated frame, CPDI, domains migrating) on 2 ranks: the serial run's files"
# boxes (--ranks-grid): DGMPM on the plate (2 x 2) and a small block (2 x 2 x 1) on 4 ranks,
# MPM (total Lagrangian) and FEM on the plate (2 x 2), write the serial files byte for byte
# (profiles, grid files; metrics to the energy's round-off)
for case in "dgmpm plate 2,2" "dgmpm block 2,2,1 --cells 16 --no-reference" "mpm plate 2,2" "fem plate 2,2"; do
  read -r method scene grid extra <<<"$case"
  serial="$work/boxes-$method-$scene-serial"
  out="$work/boxes-$method-$scene-np4"
  # shellcheck disable=SC2086
  RAYON_NUM_THREADS=1 "$bin" run "$scene" --method "$method" --quiet --out "$serial" $extra >/dev/null
  # shellcheck disable=SC2086
  RAYON_NUM_THREADS=1 "${mpi[@]}" -np 4 "$bin" run "$scene" --method "$method" --ranks-grid "$grid" \
    --quiet --out "$out" $extra >"$out.log" 2>&1 || fail "$method $scene on boxes $grid failed: $(tail -5 "$out.log")"
  same_as_serial "$method $scene on boxes $grid" "$serial" "$out" "$method" 4
  python3 - "$out/summary.json" "${grid//,/ × }" <<'PY' || fail "$method $scene on boxes $grid: summary.json"
import json, sys
rb, grid = json.load(open(sys.argv[1]))["runs"][0], sys.argv[2]
assert rb["ranks"] == 4 and f"boxes (rank grid {grid}," in rb["decomposition"], rb["decomposition"]
PY
  echo "mpi: $scene ($method) on 4 ranks as boxes $grid: files equal to the serial run bit for bit"
done

# the converged reference on 2 ranks with an empty cache folder: run decomposed, rank 0
# writes the one-rank cache entries byte for byte and the metrics are one rank's; a second
# run reads both entries (rank 0 reads, the others receive them) and computes nothing
cache_one="$work/cache-one" cache_two="$work/cache-two"
serial="$work/refranks-serial" out="$work/refranks-np2"
IMPACT_CACHE_DIR="$cache_one" RAYON_NUM_THREADS=1 "$bin" run plate --method dgmpm --cells 16 \
  --quiet --out "$serial" >/dev/null
IMPACT_CACHE_DIR="$cache_two" RAYON_NUM_THREADS=1 "${mpi[@]}" -np 2 "$bin" run plate --method dgmpm \
  --cells 16 --out "$out" >"$out.log" 2>&1 || fail "the reference on 2 ranks failed: $(tail -5 "$out.log")"
[ "$(find "$cache_two" -name '*.ref' | wc -l)" = 2 ] || fail "the reference on 2 ranks: not 2 cache entries"
for f in "$cache_one"/*.ref; do
  cmp -s "$f" "$cache_two/$(basename "$f")" || fail "the reference on 2 ranks: $(basename "$f") differs from one rank's"
done
grep -q "computing the converged reference" "$out.log" || fail "the reference on 2 ranks: not computed"
same_as_serial "dgmpm plate, its reference computed on 2 ranks" "$serial" "$out" dgmpm 2
IMPACT_CACHE_DIR="$cache_two" RAYON_NUM_THREADS=1 "${mpi[@]}" -np 2 "$bin" run plate --method dgmpm \
  --cells 16 --out "$out-again" >"$out-again.log" 2>&1 || fail "the reference read on 2 ranks failed"
[ "$(grep -c "read from the cache" "$out-again.log")" = 2 ] && ! grep -q "computing the" "$out-again.log" ||
  fail "the reference on 2 ranks: not read from the cache: $(cat "$out-again.log")"
same_as_serial "dgmpm plate, its reference read on 2 ranks" "$serial" "$out-again" dgmpm 2
echo "mpi: the plate's converged reference on 2 ranks: the one-rank cache entries byte for byte, then read"

# impact check and bench convergence under mpirun, unchanged: the same report and files as
# one rank (check's runs are decomposed, its energies differ by round-off only, which the
# report does not print; the convergence ladder's runs are decomposed too, their errors
# those of the gathered samples: the table and CSV byte for byte, the JSON's full-precision
# errors to 1e-12 relative, MPM's fields being round-off from one rank's; only rank 0
# writes: no two ranks contend for one folder)
RAYON_NUM_THREADS=1 "$bin" check plate --quiet --json "$work/check1.json" >"$work/check1.out"
RAYON_NUM_THREADS=1 "${mpi[@]}" -np 2 "$bin" check plate --quiet --json "$work/check2.json" \
  >"$work/check2.out" 2>"$work/check2.err" || fail "check on 2 ranks failed: $(tail -5 "$work/check2.err")"
cmp -s "$work/check1.out" "$work/check2.out" || fail "check on 2 ranks printed another report than on one"
python3 - "$work/check1.json" "$work/check2.json" <<'PY' || fail "check on 2 ranks: its JSON differs"
import json, sys
a, b = (json.load(open(p)) for p in sys.argv[1:3])
assert a["pass"] == b["pass"] and len(a["reports"]) == len(b["reports"])
for ra, rb in zip(a["reports"], b["reports"]):
    assert ra["pass"] == rb["pass"] and ra["rows"] == rb["rows"], (ra["rows"], rb["rows"])
PY
for n in 1 2; do
  launch=()
  [ "$n" = 1 ] || launch=("${mpi[@]}" -np "$n")
  RAYON_NUM_THREADS=1 "${launch[@]}" "$bin" bench convergence --scene plate --levels 2 --out "$work/conv$n" \
    >"$work/conv$n.out" 2>&1 || fail "bench convergence on $n ranks failed: $(tail -5 "$work/conv$n.out")"
done
for f in convergence.csv convergence.txt; do
  cmp -s "$work/conv1/$f" "$work/conv2/$f" || fail "bench convergence on 2 ranks: $f differs from one rank's"
done
python3 - "$work/conv1/convergence.json" "$work/conv2/convergence.json" <<'PY' || fail "bench convergence on 2 ranks: its JSON differs from one rank's beyond round-off"
import json, sys
a, b = (json.load(open(p)) for p in sys.argv[1:3])
assert len(a) == len(b), (len(a), len(b))
for ra, rb in zip(a, b):
    assert ra.keys() == rb.keys(), (ra, rb)
    for k, va in ra.items():
        vb = rb[k]
        if isinstance(va, float):
            assert abs(va - vb) <= 1e-12 * abs(va), (ra["config"], k, va, vb)
        else:
            assert va == vb, (k, va, vb)
PY
[ "$(grep -c ' cells: L2' "$work/conv2.out")" = "$(grep -c ' cells: L2' "$work/conv1.out")" ] \
  || fail "bench convergence on 2 ranks: its progress lines are printed by more than rank 0"
echo "mpi: impact check and bench convergence on 2 ranks: the one-rank report and files"
# bench work-precision: on one rank each run is a child process, on several the same study
# split over the ranks in this process; the bar's errors, steps and cells as one rank's (the
# errors to 1e-12: the child's study and the in-process one differ in a last digit, and
# MPM's fields are round-off from one rank's), timings and memory their own
for n in 1 2; do
  launch=()
  [ "$n" = 1 ] || launch=("${mpi[@]}" -np "$n")
  RAYON_NUM_THREADS=1 "${launch[@]}" "$bin" bench work-precision --scene bar --levels 2 --out "$work/wp$n" \
    >"$work/wp$n.out" 2>&1 || fail "bench work-precision on $n ranks failed: $(tail -5 "$work/wp$n.out")"
done
python3 - "$work/wp1/work_precision.json" "$work/wp2/work_precision.json" <<'PY' || fail "bench work-precision on 2 ranks: its runs differ from one rank's"
import json, sys
a, b = (json.load(open(p)) for p in sys.argv[1:3])
assert len(a) == len(b) > 0, (len(a), len(b))
for ra, rb in zip(a, b):
    for k in ("scene", "config", "cells_x", "cells", "steps", "error"):
        assert ra.get(k) == rb.get(k), (ra["config"], k, ra.get(k), rb.get(k))
    for k in ("l1_rel", "l1_spread"):
        assert (k in ra) == (k in rb) and abs(ra.get(k, 0) - rb.get(k, 0)) <= 1e-12, (ra["config"], k)
PY
[ "$(wc -l <"$work/wp2.out")" = "$(wc -l <"$work/wp1.out")" ] \
  || fail "bench work-precision on 2 ranks: its lines are printed by more than rank 0"
echo "mpi: bench work-precision on 2 ranks: the one-rank errors, steps and cells"

# failures stop every rank with one message and a non-zero exit (no hang: `timeout`)
expect_failure() { # code pattern args...
  expect_failure_of "$1" "$2" -np 3 "$bin" "${@:3}" --quiet --out "$work/failing"
}
expect_failure_of() { # code pattern mpirun-args...
  local code="$1" pattern="$2"
  shift 2
  set +e
  "${mpi[@]}" "$@" >"$work/fail.out" 2>"$work/fail.err"
  local rc=$?
  set -e
  [ "$rc" -ne 124 ] || fail "$* hung on 3 ranks"
  [ "$rc" -ne 0 ] || fail "$* succeeded on 3 ranks"
  local lines
  lines=$(grep -c "^error: " "$work/fail.err" || true)
  [ "$lines" = 1 ] || fail "$*: $lines error lines (one expected): $(cat "$work/fail.err")"
  grep -q "^error: .*$pattern" "$work/fail.err" || fail "$*: message lacks '$pattern': $(cat "$work/fail.err")"
  [ "$rc" = "$code" ] || fail "$*: exit code $rc, not $code: $(cat "$work/fail.err")"
}
expect_failure 2 "courant.*7" run plate --method dgmpm --courant 7
expect_failure 3 "blew up" run plate --method dgmpm --courant 1.5 --allow-unstable
expect_failure 2 "ranks-grid 2,2: its product is 4 but the run has 3 ranks" run plate --method dgmpm --ranks-grid 2,2
echo "mpi: a bad input and a blow-up stop all 3 ranks with one message"
# a failure on some ranks only: rank 0 cannot make its output folder (under /proc); ranks 1
# and 2 cannot make their scratch folders (TMPDIR under /proc, MPMD launch) while rank 0 can
expect_failure_of 2 "rank 0: .*impact-out" -np 3 "$bin" run plate --method dgmpm --quiet --out /proc/impact-out
expect_failure_of 2 "rank 1: " -np 1 "$bin" run plate --method dgmpm --quiet --out "$work/one-fails" \
  : -np 2 env TMPDIR=/proc/impact-tmp "$bin" run plate --method dgmpm --quiet --out "$work/one-fails"
[ ! -e "$work/one-fails/manifest.json" ] || fail "a failing rank: rank 0 published its folder"
echo "mpi: a folder that rank 0 only, or ranks 1-2 only, cannot write stops all 3 ranks with one message"

# kill -9 of one rank: mpirun ends the others, and the output folder is never presented as
# complete (rank 0 writes into a staging folder that replaces the target only when done)
"${mpi[@]}" -np 2 "$bin" run plate --cells 600 --method dgmpm --no-reference --quiet \
  --out "$work/killed" >/dev/null 2>&1 &
launcher=$!
victim=""
ranks=""
for _ in $(seq 200); do
  runner=$(pgrep -P "$launcher" -x mpirun || true)
  [ -n "$runner" ] && ranks=$(pgrep -P "$runner" -x impact || true) && victim=$(echo "$ranks" | tail -n 1)
  [ -n "$victim" ] && break
  sleep 0.05
done
[ -n "$victim" ] || fail "kill -9: no rank of the run was found"
sleep 1
kill -9 "$victim"
set +e
wait "$launcher"
rc=$?
set -e
[ "$rc" -ne 124 ] || fail "kill -9 of one rank: the other rank hung"
[ "$rc" -ne 0 ] || fail "kill -9 of one rank: the run still reported success"
# (the ranks' scratch folders, named by their process ids, `src/ranks.rs`)
for pid in $ranks; do rm -rf "${TMPDIR:-/tmp}/impact-rank"*"-$pid"; done
[ ! -e "$work/killed/manifest.json" ] || fail "kill -9 of one rank: a folder was presented as complete"
echo "mpi: kill -9 of one of 2 ranks ends the run (exit $rc) with no folder presented as complete"
