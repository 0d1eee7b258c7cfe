#!/usr/bin/env bash
# Install what building and testing granmix needs beyond the Rust toolchain:
# libclang-dev (fmi-sys generates the FMI 2.0 bindings with bindgen) and, for the FMU
# and IPC tests, a Python venv in .venv with fmpy, pytest, iceoryx2, mcap and numpy.
# Safe to run again.
set -euo pipefail
cd "$(dirname "$0")/.."
if ! dpkg -s libclang-dev >/dev/null 2>&1; then
    SUDO=""
    if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi
    $SUDO apt-get update -qq && $SUDO apt-get install -y -qq libclang-dev
fi
if ! .venv/bin/python -c "import fmpy, pytest, iceoryx2, mcap, numpy" >/dev/null 2>&1; then
    python3 -m venv .venv
    .venv/bin/pip install --quiet fmpy==0.3.32 pytest iceoryx2==0.10.0 mcap==1.6.0 numpy
fi
