#!/usr/bin/env bash
# Run the whole test suite from a fresh checkout: formatting, lints, unit and
# validation tests. Installs nothing beyond the Rust toolchain for now.
set -euo pipefail
cd "$(dirname "$0")/.."
export CARGO_TERM_COLOR=never
cargo fmt --all -- --check
cargo clippy --release --all-targets -- -D warnings
cargo test --release --workspace
