#!/usr/bin/env bash
# Install what building and testing granmix needs beyond the Rust toolchain:
# libclang-dev (fmi-sys generates the FMI 2.0 bindings with bindgen), binutils (objdump
# and nm, which the FMU portability test reads the library with) and a Python venv in
# .venv with zig (the `ziglang` package: it links the FMU's library against glibc 2.28,
# see scripts/fmu-link-gcc) and, for the FMU and IPC tests, fmpy, pytest, iceoryx2, mcap
# and numpy, meshio and vtk (the outputs test reads the ParaView files with both),
# mcap-protobuf-support (it decodes the recordings' Foxglove messages), the
# granmix study package (python/, editable, with dask + distributed, bokeh, pandas,
# pyarrow, matplotlib and tqdm) and ruff (the Python lint of the test script). Safe to
# run again.
#
# `setup.sh system` installs the apt packages only, `setup.sh python` the venv only
# (scripts/test.sh builds the venv while clippy compiles); without an argument, both.
set -euo pipefail
cd "$(dirname "$0")/.."
part="${1:-all}"
case "$part" in
all | system | python) ;;
*)
    echo "scripts/setup.sh: unknown part '$part' (system, python, or none for both)" >&2
    exit 2
    ;;
esac
if [ "$part" != python ]; then
    missing=()
    if ! dpkg -s libclang-dev >/dev/null 2>&1; then missing+=(libclang-dev); fi
    if ! command -v objdump >/dev/null || ! command -v nm >/dev/null; then missing+=(binutils); fi
    if [ "${#missing[@]}" -gt 0 ]; then
        SUDO=""
        if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi
        $SUDO apt-get update -qq && $SUDO apt-get install -y -qq "${missing[@]}"
    fi
fi
if [ "$part" = system ]; then exit 0; fi
if ! .venv/bin/python -c "import fmpy, pytest, iceoryx2, mcap, numpy" >/dev/null 2>&1; then
    python3 -m venv .venv
    .venv/bin/pip install --quiet fmpy==0.3.32 pytest iceoryx2==0.10.0 mcap==1.6.0 numpy
fi
if ! .venv/bin/python -c "import ziglang" >/dev/null 2>&1; then
    .venv/bin/pip install --quiet ziglang==0.17.1
fi
# meshio and VTK's Python package: the outputs test reads the ParaView files with both
if ! .venv/bin/python -c "import meshio, vtk" >/dev/null 2>&1; then
    .venv/bin/pip install --quiet meshio==5.3.5 vtk==9.7.2
fi
# mcap-protobuf-support (and protobuf): the recording test decodes the Foxglove messages
# with the schemas stored in the file
if ! .venv/bin/python -c "import mcap_protobuf.decoder" >/dev/null 2>&1; then
    .venv/bin/pip install --quiet mcap-protobuf-support==0.6.0 protobuf==7.36.2
fi
# the granmix study package (python/), editable: the tests import it from the checkout;
# with its dependencies (bokeh for the Dask dashboard, tqdm for the progress bar)
if ! .venv/bin/python -c "import granmix.sweep, distributed, matplotlib, bokeh, tqdm" \
    >/dev/null 2>&1; then
    .venv/bin/pip install --quiet -e python
fi
# ruff, pinned: its default rule set changes between releases
if [ "$(.venv/bin/ruff --version 2>/dev/null)" != "ruff 0.17.6" ]; then
    .venv/bin/pip install --quiet ruff==0.17.6
fi
