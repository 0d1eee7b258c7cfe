"""Where a study's FMUs are extracted while their cases run, and the clearing of what
dead processes left there.

Each instance extracts its FMU (about 9 MB for the granmix FMU) into a directory of its
own under ``<pack cache>/extracted/``, named ``<host>-<pid>-…`` after the process that
made it, and removes it when the case ends. A process that is killed (a worker that
ran out of memory, a LocalCluster's workers killed after a Ctrl-C) cannot. A Dask
worker that is shut down clears its own (:func:`clear_own`, from the worker plugin the
study registers), and for those that are killed outright the next
study that uses the same cache, and every worker process before its first case, clears
the directories of processes of its own host that are no longer alive. Directories of
other hosts (a shared file system) are left to those hosts.
"""

from __future__ import annotations

import os
import shutil
import socket
import tempfile
from pathlib import Path

#: The directory under a pack cache that holds the extracted FMUs.
SUBDIR = "extracted"


def _host() -> str:
    # a host name with `-` kept apart from the pid that follows it
    return socket.gethostname().replace("-", "_")


def root(cache_dir: Path) -> Path:
    return Path(cache_dir) / SUBDIR


def make(cache_dir: Path) -> Path:
    """A new directory to extract one FMU into, named after this process."""
    r = root(cache_dir)
    r.mkdir(parents=True, exist_ok=True)
    return Path(tempfile.mkdtemp(prefix=f"{_host()}-{os.getpid()}-", dir=r))


def _alive(pid: int) -> bool:
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:
        return True
    return True


def clear_stale(cache_dir: Path) -> int:
    """Remove the extraction directories of this host's processes that are gone;
    returns how many."""
    r = root(cache_dir)
    if not r.is_dir():
        return 0
    host, n = _host(), 0
    for d in r.iterdir():
        parts = d.name.split("-")
        if len(parts) < 3 or parts[0] != host or not parts[1].isdigit():
            continue
        if not _alive(int(parts[1])):
            shutil.rmtree(d, ignore_errors=True)
            n += 1
    return n


def clear_own(cache_dir: Path) -> int:
    """Remove the extraction directories of this process (at its shutdown: the cases
    it was running when it was stopped could not); returns how many."""
    r = root(cache_dir)
    if not r.is_dir():
        return 0
    prefix, n = f"{_host()}-{os.getpid()}-", 0
    for d in r.iterdir():
        if d.name.startswith(prefix):
            shutil.rmtree(d, ignore_errors=True)
            n += 1
    return n
