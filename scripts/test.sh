#!/usr/bin/env bash
# The test command (README, .ci/run): formatting, lints, every Rust test, and the Python
# cross-checks under scripts/ when there are any (run in scripts/.venv, made if missing).
set -euo pipefail
cd "$(dirname "$0")/.."

if ! cargo fmt --version >/dev/null 2>&1 || ! cargo clippy --version >/dev/null 2>&1; then
  rustup component add rustfmt clippy
fi
cargo fmt --all -- --check
cargo clippy --all-targets -- -D warnings
cargo test --workspace --release

shopt -s nullglob
python_tests=(scripts/test_*.py scripts/crosscheck_*.py)
if [ ${#python_tests[@]} -gt 0 ]; then
  venv=scripts/.venv
  if [ ! -x "$venv/bin/python" ]; then
    python3 -m venv "$venv"
    "$venv/bin/python" -m pip install --quiet --upgrade pip
    "$venv/bin/python" -m pip install --quiet -r scripts/requirements.txt
  fi
  cargo build --release
  IMPACT_BIN="$PWD/target/release/impact" "$venv/bin/python" -m pytest -q "${python_tests[@]}"
fi
