#!/usr/bin/env bash
# Run the whole test suite from a fresh checkout: formatting, lints, unit and
# validation tests, then the FMU tests in Python (pytest + fmpy in .venv).
# Installs what it needs: libclang-dev (fmi-sys runs bindgen) and the Python venv.
set -euo pipefail
cd "$(dirname "$0")/.."
export CARGO_TERM_COLOR=never
if ! dpkg -s libclang-dev >/dev/null 2>&1; then
    apt-get update && apt-get install -y libclang-dev
fi
if ! .venv/bin/python -c "import fmpy, pytest" >/dev/null 2>&1; then
    python3 -m venv .venv
    .venv/bin/pip install --quiet fmpy==0.3.32 pytest
fi
cargo fmt --all -- --check
cargo clippy --release --all-targets -- -D warnings
cargo test --release --workspace
# the FMU tests pack FMUs with the granmix binary and the granmix-fmu library
cargo build --release -p granmix -p granmix-fmu
.venv/bin/python -m pytest -q tests/python
