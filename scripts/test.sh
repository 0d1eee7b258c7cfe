#!/usr/bin/env bash
# Run the whole test suite from a fresh checkout: formatting, lints (clippy, ruff), unit
# and validation tests, then the FMU tests in Python (pytest + fmpy in .venv).
# Installs what it needs first (scripts/setup.sh: libclang-dev and the Python venv).
set -euo pipefail
cd "$(dirname "$0")/.."
export CARGO_TERM_COLOR=never
bash scripts/setup.sh system
# The Python venv builds while cargo compiles (a minute and a half on a fresh checkout);
# the FMU library's link (scripts/fmu-link-gcc) waits for the venv's zig.
venv_log="$(mktemp)"
GRANMIX_VENV_PENDING="$(mktemp)"
export GRANMIX_VENV_PENDING
(
    status=0
    bash scripts/setup.sh python >"$venv_log" 2>&1 || status=$?
    rm -f "$GRANMIX_VENV_PENDING"
    exit "$status"
) &
venv=$!
cargo fmt --all -- --check
cargo test --release --workspace --no-run
# the FMU tests pack FMUs with the granmix binary and the granmix-fmu library
cargo build --release --workspace
if ! wait "$venv"; then
    cat "$venv_log" >&2
    echo "scripts/test.sh: scripts/setup.sh python failed (its output above)" >&2
    exit 1
fi
cat "$venv_log"
rm -f "$venv_log"
.venv/bin/ruff check python tests/python scripts examples
cargo test --release --workspace
# clippy checks while the FMU tests run (they keep one core busy, clippy the other)
clippy_log="$(mktemp)"
cargo clippy --release --all-targets -- -D warnings >"$clippy_log" 2>&1 &
clippy=$!
.venv/bin/python -m pytest -q tests/python
if ! wait "$clippy"; then
    cat "$clippy_log" >&2
    echo "scripts/test.sh: cargo clippy failed (its output above)" >&2
    exit 1
fi
cat "$clippy_log"
rm -f "$clippy_log"
# smoke runs of the accuracy, soil-model, stability, scale and FMI-overhead suites on tiny cases (the
# full suites are benchmarks)
smoke="$(mktemp -d)"
"${CARGO_TARGET_DIR:-target}"/release/granmix bench --suite accuracy --quick --out "$smoke"
"${CARGO_TARGET_DIR:-target}"/release/granmix bench --suite models --quick --out "$smoke"
"${CARGO_TARGET_DIR:-target}"/release/granmix bench --suite stability --quick --out "$smoke"
"${CARGO_TARGET_DIR:-target}"/release/granmix bench --suite scale --quick --out "$smoke"
"${CARGO_TARGET_DIR:-target}"/release/granmix bench --suite fmi --quick --out "$smoke"
rm -rf "$smoke"
