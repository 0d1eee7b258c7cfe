"""FMUs for a study's cases, packed once: the granmix scene with a case's scene keys as
``--set`` overrides, and partner structure files. A packed FMU is named by a hash of
its source file, its overrides and the ``granmix`` executable, and written atomically, so
workers sharing the cache directory never see half a file and pack each distinct FMU
once (two workers racing on the same one both write it whole; the last rename wins).
"""

from __future__ import annotations

import hashlib
import os
import shutil
import subprocess
import tempfile
from pathlib import Path


class PackError(RuntimeError):
    """``granmix pack-fmu`` refused a source; the message is granmix's own."""


def granmix_executable() -> Path:
    """The ``granmix`` executable: ``GRANMIX_BIN``, else the checkout's release build
    (``CARGO_TARGET_DIR`` or ``target/``), else ``granmix`` on the PATH."""
    if "GRANMIX_BIN" in os.environ:
        return Path(os.environ["GRANMIX_BIN"])
    root = Path(__file__).resolve().parents[2]
    target = Path(os.environ.get("CARGO_TARGET_DIR", root / "target"))
    built = target / "release" / "granmix"
    if built.is_file():
        return built
    found = shutil.which("granmix")
    if found is None:
        raise PackError(
            "no granmix executable: build it (cargo build --release) or set GRANMIX_BIN"
        )
    return Path(found)


class PackCache:
    """Packed FMUs under ``directory``."""

    def __init__(self, directory: str | Path, executable: Path | None = None) -> None:
        self.dir = Path(directory)
        self.dir.mkdir(parents=True, exist_ok=True)
        self.exe = executable or granmix_executable()
        self._exe_digest = _file_digest(self.exe)
        #: FMUs packed by this cache object (the others were found packed).
        self.packed = 0

    def fmu(self, source: Path, sets: tuple[str, ...] = ()) -> Path:
        """The FMU of ``source`` (an .fmu is used as it is) with overrides ``sets``."""
        if source.suffix == ".fmu":
            return source
        h = hashlib.sha256()
        h.update(self._exe_digest.encode())
        h.update(source.read_bytes())
        for s in sets:
            h.update(b"\0" + s.encode())
        out = self.dir / f"{source.stem}-{h.hexdigest()[:16]}.fmu"
        if out.is_file():
            return out
        fd, tmp = tempfile.mkstemp(suffix=".fmu", dir=self.dir)
        os.close(fd)
        cmd = [str(self.exe), "pack-fmu", str(source), "-o", tmp]
        for s in sets:
            cmd += ["--set", s]
        r = subprocess.run(cmd, check=False, capture_output=True, text=True)
        if r.returncode != 0:
            os.unlink(tmp)
            raise PackError(r.stderr.strip() or f"granmix pack-fmu {source} failed")
        os.replace(tmp, out)
        self.packed += 1
        return out


def _file_digest(path: Path) -> str:
    h = hashlib.sha256()
    with open(path, "rb") as f:
        for block in iter(lambda: f.read(1 << 20), b""):
            h.update(block)
    return h.hexdigest()
