#!/usr/bin/env bash
# The test command (README, .ci/run): formatting, lints, every Rust test, and the Python
# cross-checks under scripts/ (in scripts/.venv, made if missing). When the system HDF5
# library is present, or can be installed (root with apt), the `hdf5` feature is linted,
# built and cross-checked too; likewise OpenMPI for the `mpi` feature (scripts/mpi_check.sh).
set -euo pipefail
cd "$(dirname "$0")/.."
# each phase prints its start (seconds since the run began), so CI logs show where time goes
phase() { echo "== test.sh: $1 (at ${SECONDS} s)"; }

as_root() {
  if [ "$(id -u)" = 0 ]; then "$@"; elif command -v sudo >/dev/null 2>&1; then sudo -n "$@"; else return 1; fi
}
apt_install() {
  command -v apt-get >/dev/null 2>&1 || return 1
  as_root env DEBIAN_FRONTEND=noninteractive apt-get install -y -q "$@" >/dev/null 2>&1 && return 0
  as_root apt-get update -q >/dev/null 2>&1 || return 1
  as_root env DEBIAN_FRONTEND=noninteractive apt-get install -y -q "$@" >/dev/null 2>&1
}

if ! cargo fmt --version >/dev/null 2>&1 || ! cargo clippy --version >/dev/null 2>&1; then
  rustup component add rustfmt clippy
fi
phase "fmt, clippy, docs"
cargo fmt --all -- --check
cargo clippy --workspace --all-targets -- -D warnings
# the API docs build without broken or private links
RUSTDOCFLAGS="-D warnings" cargo doc --workspace --no-deps --quiet
phase "cargo test --release"
cargo test --workspace --release

# HDF5 (optional feature): needs Debian's libhdf5-dev, installed here (apt) if missing;
# the test run fails with the reason when it cannot be installed (never a silent skip)
if ! pkg-config --exists hdf5 2>/dev/null && [ ! -f /usr/include/hdf5/serial/hdf5.h ]; then
  apt_install libhdf5-dev pkg-config || {
    echo "hdf5: cannot install libhdf5-dev (needs apt as root or sudo); the hdf5 feature's checks cannot run" >&2
    exit 1
  }
fi

# MPI (optional feature `mpi`, issue 27): needs Debian's OpenMPI and libclang (rsmpi's
# bindings), installed here (apt) if missing; the test run fails with the reason when they
# cannot be installed (never a silent skip). One binary with both features serves the MPI
# checks and the Python cross-checks below (without mpirun it runs on one rank).
if ! command -v mpirun >/dev/null 2>&1 || ! command -v mpicc >/dev/null 2>&1 \
  || ! compgen -G "/usr/lib/llvm-*/lib/libclang*.so*" >/dev/null; then
  apt_install openmpi-bin libopenmpi-dev libclang-dev || {
    echo "mpi: cannot install openmpi-bin libopenmpi-dev libclang-dev (needs apt as root or sudo); the mpi feature's checks cannot run" >&2
    exit 1
  }
fi
features=(--features hdf5,mpi)
phase "hdf5,mpi: clippy and release build"
cargo clippy --all-targets "${features[@]}" -- -D warnings
cargo build --release "${features[@]}"
echo "hdf5: feature linted and built (its files are cross-checked by scripts/crosscheck_*.py below)"
# DGMPM on bar and plate under mpirun -np 1..4 against the serial run; failing ranks
phase "mpi_check.sh"
bash scripts/mpi_check.sh target/release/impact

shopt -s nullglob
python_tests=(scripts/crosscheck_*.py scripts/test_*.py)
if [ ${#python_tests[@]} -gt 0 ]; then
  venv=scripts/.venv
  if [ ! -x "$venv/bin/python" ] || ! "$venv/bin/python" -c "import skfem, pyvista, meshio, h5py, pytest" 2>/dev/null; then
    rm -rf "$venv"
    python3 -m venv "$venv" 2>/dev/null || { apt_install python3-venv && python3 -m venv "$venv"; }
    "$venv/bin/python" -m pip install --quiet --upgrade pip
    "$venv/bin/python" -m pip install --quiet -r scripts/requirements.txt
  fi
  # Clawpack (scripts/crosscheck_clawpack.py) builds its Fortran Riemann solvers at install
  # time: it needs gfortran (apt); the run fails with the reason when either cannot be had
  if ! "$venv/bin/python" -c "import clawpack.pyclaw, clawpack.riemann.vc_elasticity_2D, clawpack.riemann.acoustics_1D" 2>/dev/null; then
    command -v gfortran >/dev/null 2>&1 || apt_install gfortran || {
      echo "clawpack: cannot install gfortran (needs apt as root or sudo); crosscheck_clawpack.py cannot run" >&2
      exit 1
    }
    "$venv/bin/python" -m pip install --quiet "clawpack==5.14.0" || {
      echo "clawpack: pip install clawpack==5.14.0 failed; crosscheck_clawpack.py cannot run" >&2
      exit 1
    }
  fi
  phase "python cross-checks"
  IMPACT_BIN="$PWD/target/release/impact" IMPACT_HAS_HDF5=1 \
    "$venv/bin/python" -m pytest -q -rs -p no:cacheprovider "${python_tests[@]}"

  # The Python package (crates/impact-py): maturin and pandas into the test venv, the
  # package built from this tree and installed (editable), its tests (the CLI's files
  # compared bit for bit, the examples run); an install that fails stops the run with why
  if ! "$venv/bin/python" -c "import maturin, pandas, tqdm" 2>/dev/null; then
    "$venv/bin/python" -m pip install --quiet -r scripts/requirements-py.txt || {
      echo "impact-py: pip install -r scripts/requirements-py.txt failed; the package's tests cannot run" >&2
      exit 1
    }
  fi
  phase "impact-py: maturin develop"
  VIRTUAL_ENV="$PWD/$venv" "$venv/bin/python" -m maturin develop --release --quiet \
    -m crates/impact-py/Cargo.toml || {
    echo "impact-py: maturin develop failed; the package's tests cannot run" >&2
    exit 1
  }
  phase "impact-py tests"
  IMPACT_BIN="$PWD/target/release/impact" \
    "$venv/bin/python" -m pytest -q -rs -p no:cacheprovider crates/impact-py/tests
fi
phase "done"
