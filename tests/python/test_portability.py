"""The packed FMU's shared library: it loads on glibc 2.28 (RHEL/Rocky 8, Ubuntu 20.04),
carries no debug info, keeps the FMU under 4 MB and exports exactly the FMI 2.0
Co-Simulation functions (scripts/fmu-link-gcc; docs/fmu.md, "Portability").
test_validate.py and test_simulate.py load and run the same library in fmpy."""

import re
import shutil
import subprocess
import zipfile

import pytest

# The FMI 2.0 functions a Co-Simulation FMU exports (FMI 2.0.4, sections 2.1 and 4.2).
FMI2_CS_FUNCTIONS = {
    "fmi2GetTypesPlatform", "fmi2GetVersion", "fmi2SetDebugLogging",
    "fmi2Instantiate", "fmi2FreeInstance", "fmi2SetupExperiment",
    "fmi2EnterInitializationMode", "fmi2ExitInitializationMode", "fmi2Terminate",
    "fmi2Reset", "fmi2GetReal", "fmi2GetInteger", "fmi2GetBoolean", "fmi2GetString",
    "fmi2SetReal", "fmi2SetInteger", "fmi2SetBoolean", "fmi2SetString",
    "fmi2GetFMUstate", "fmi2SetFMUstate", "fmi2FreeFMUstate",
    "fmi2SerializedFMUstateSize", "fmi2SerializeFMUstate", "fmi2DeSerializeFMUstate",
    "fmi2GetDirectionalDerivative", "fmi2SetRealInputDerivatives",
    "fmi2GetRealOutputDerivatives", "fmi2DoStep", "fmi2CancelStep", "fmi2GetStatus",
    "fmi2GetRealStatus", "fmi2GetIntegerStatus", "fmi2GetBooleanStatus",
    "fmi2GetStringStatus",
}
OLDEST_GLIBC = (2, 28)
MAX_FMU_BYTES = 4_000_000


def tool(name):
    path = shutil.which(name)
    if path is None:
        pytest.fail(f"`{name}` not found: install binutils (scripts/setup.sh does)")
    return path


@pytest.fixture(scope="module")
def library(fmus, tmp_path_factory):
    """The shared library inside the packed barrier FMU."""
    with zipfile.ZipFile(fmus["barrier"]) as z:
        data = z.read("binaries/linux64/barrier.so")
    path = tmp_path_factory.mktemp("lib") / "barrier.so"
    path.write_bytes(data)
    return path


def run(*cmd):
    return subprocess.run(cmd, check=True, capture_output=True, text=True).stdout


def test_needs_at_most_glibc_2_28(library):
    table = run(tool("objdump"), "-T", str(library))
    needs = {}  # symbol -> glibc version it is bound to
    for line in table.splitlines():
        m = re.search(r"\bGLIBC_(\d+(?:\.\d+)+)\b", line)
        if m:
            needs[line.split()[-1]] = tuple(int(x) for x in m.group(1).split("."))
    assert needs, "no GLIBC symbol versions found: objdump -T output changed?"
    newer = sorted(f"{s} (GLIBC_{'.'.join(map(str, v))})" for s, v in needs.items() if v > OLDEST_GLIBC)
    assert not newer, f"the FMU library needs a glibc newer than 2.28 for {', '.join(newer)}"


def test_no_debug_info_and_small(library, fmus):
    sections = run(tool("objdump"), "-h", str(library))
    debug = sorted(set(re.findall(r"\s(\.debug_\w+)\s", sections)))
    assert not debug, f"the FMU library carries debug sections {debug}"
    size = fmus["barrier"].stat().st_size
    assert size < MAX_FMU_BYTES, f"the FMU is {size} bytes, over {MAX_FMU_BYTES}"


def test_exports_exactly_the_fmi2_functions(library):
    table = run(tool("nm"), "-D", "--defined-only", str(library))
    names = {line.split()[-1] for line in table.splitlines() if line.strip()}
    assert names == FMI2_CS_FUNCTIONS, (
        f"missing {sorted(FMI2_CS_FUNCTIONS - names)}, stray {sorted(names - FMI2_CS_FUNCTIONS)}"
    )
