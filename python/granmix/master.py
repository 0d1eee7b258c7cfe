"""One case of a study: the co-simulation master loop over the granmix FMU and its
partners, and the case's result row.

The loop is the Gauss–Seidel loop of ``docs/fmu.md``: at every communication step the
partners step first, in the study's order, each fed the latest outputs of its sources,
then the granmix FMU, fed the partners' new outputs. The collected outputs are read at
t = 0 and after every step and reduced over time (``max``, ``min``, ``final``, ``mean``,
``integral``, the last two by the trapezoidal rule). A case whose FMU fails (the
stability guard, a refused input or start value, any FMI error) or that outlasts the
study's wall-time limit becomes a ``failed`` row carrying the FMU's logged message or
the reason; it never raises. Every instance a case made is freed and its extracted
directory removed, whatever happened.
"""

from __future__ import annotations

import contextlib
import itertools
import os
import shutil
import socket
import time
from ctypes import byref
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from fmpy import calloc, extract, free, read_model_description
from fmpy.fmi2 import (
    FMU2Slave,
    fmi2CallbackAllocateMemoryTYPE,
    fmi2CallbackFreeMemoryTYPE,
    fmi2CallbackFunctions,
    fmi2CallbackLoggerTYPE,
    printLogMessage,
)

from granmix import extracted
from granmix.design import Case
from granmix.pack import PackCache
from granmix.study import GRANMIX, Study

try:
    from fmpy.logging import addLoggerProxy
except (ImportError, OSError, AttributeError):  # fmpy ships the proxy for this platform
    addLoggerProxy = None


@dataclass
class CaseResult:
    """The result row of one case and its time series."""

    key: str
    index: int
    values: dict[str, Any]
    status: str
    diagnostic: str = ""
    outputs: dict[str, float] = field(default_factory=dict)
    wall_time: float = 0.0
    #: Seconds spent finding or packing the FMUs and instantiating them, in the
    #: master loop (the solvers and the FMI calls), and terminating.
    setup_time: float = 0.0
    loop_time: float = 0.0
    close_time: float = 0.0
    #: The machine and the worker that ran the case: ``<hostname>/<worker name>`` on
    #: Dask, ``<hostname>/serial`` in the client.
    host: str = ""
    #: ``time`` and every collected output, sampled at t = 0 and after every step (up
    #: to the failure, for a failed case).
    series: dict[str, list[float]] = field(default_factory=dict)

    def row(self) -> dict[str, Any]:
        """One flat row: key, index, parameter values, reduced outputs, status,
        diagnostic, wall time and host."""
        out: dict[str, Any] = {"key": self.key, "case": self.index}
        out.update(self.values)
        out.update(self.outputs)
        out.update(
            status=self.status,
            diagnostic=self.diagnostic,
            wall_time=self.wall_time,
            setup_time=self.setup_time,
            loop_time=self.loop_time,
            close_time=self.close_time,
            host=self.host,
        )
        return out


_ERROR_CATEGORIES = ("logStatusError", "logStatusFatal")

#: The live instances by their FMI component environment (the key each instance gives
#: its FMU, which the FMU passes back with every log message).
_LOGGING: dict[int, _Instance] = {}
_KEYS = itertools.count(1)


def _dispatch(env: Any, name: Any, status: int, category: Any, message: Any) -> None:
    """The one logger every instance's callbacks name: the message goes to the instance
    whose environment it carries, else to fmpy's own printer.

    fmpy's native proxy, which formats a message's variadic arguments, keeps a single,
    process-wide pointer to the Python logger it forwards to, set by each
    ``addLoggerProxy`` call. Were each instance to register a logger of its own, that
    pointer would route every proxied message (other instances', and fmpy's own
    FMUs' after the study) to the last instance registered, and to freed memory once
    that instance was collected: a later ``fmpy.simulate_fmu`` in the same process
    crashed on its first log message. This function lives as long as the process, so
    the pointer never dangles."""
    inst = _LOGGING.get(env or 0)
    if inst is None:
        printLogMessage(env, name, status, category, message)
        return
    inst.logged(status, category, message)


_LOGGER = fmi2CallbackLoggerTYPE(_dispatch)


class CaseTimeout(RuntimeError):
    """A case outlasted the study's wall-time limit."""


class _Instance:
    """An FMU instance with variables by name and its log messages kept.

    Made in two steps so that a caller holds it before anything can fail: the
    constructor extracts the FMU and loads its library, :meth:`start` instantiates and
    initialises it. :meth:`close` frees whatever was made and removes the extracted
    directory."""

    def __init__(self, name: str, path: Path, cache_dir: Path | None = None) -> None:
        self.name = name
        md = read_model_description(str(path))
        self.vr = {v.name: v.valueReference for v in md.modelVariables}
        self.log: list[tuple[int, str, str]] = []
        self.live = False
        self.fmu: FMU2Slave | None = None
        # a directory of this process's under the pack cache (granmix.extracted), so
        # that one a killed process leaves is cleared by the next
        into = extracted.make(cache_dir) if cache_dir is not None else None
        try:
            self.dir = extract(str(path), unzipdir=str(into) if into else None)
        except BaseException:
            if into is not None:
                shutil.rmtree(into, ignore_errors=True)
            raise
        self.key = next(_KEYS)
        _LOGGING[self.key] = self
        self.callbacks = fmi2CallbackFunctions()
        self.callbacks.componentEnvironment = self.key
        self.callbacks.logger = _LOGGER
        self.callbacks.allocateMemory = fmi2CallbackAllocateMemoryTYPE(calloc)
        self.callbacks.freeMemory = fmi2CallbackFreeMemoryTYPE(free)
        if addLoggerProxy is not None:
            addLoggerProxy(byref(self.callbacks))
        try:
            self.fmu = FMU2Slave(
                guid=md.guid,
                unzipDirectory=self.dir,
                modelIdentifier=md.coSimulation.modelIdentifier,
                instanceName=name,
            )
        except BaseException:
            # a library that does not load: nothing to free, the directory to remove
            _LOGGING.pop(self.key, None)
            shutil.rmtree(self.dir, ignore_errors=True)
            raise

    def start(self, start: dict[str, float]) -> None:
        """Instantiate, set the start values ``start`` and initialise."""
        assert self.fmu is not None
        self.fmu.instantiate(callbacks=self.callbacks)
        self.live = True
        self.fmu.setupExperiment(startTime=0.0)
        self.fmu.enterInitializationMode()
        for k, v in start.items():
            self.set(k, v)
        self.fmu.exitInitializationMode()

    def logged(self, status: int, category: Any, message: Any) -> None:
        """Keep one message the FMU logged."""
        cat = category.decode(errors="replace") if category else ""
        self.log.append((int(status), cat, message.decode(errors="replace") if message else ""))

    def ref(self, variable: str) -> int:
        try:
            return self.vr[variable]
        except KeyError:
            raise KeyError(f"FMU `{self.name}` has no variable `{variable}`") from None

    def get(self, variable: str) -> float:
        assert self.fmu is not None
        return self.fmu.getReal([self.ref(variable)])[0]

    def set(self, variable: str, value: float) -> None:
        assert self.fmu is not None
        try:
            self.fmu.setReal([self.ref(variable)], [float(value)])
        except Exception as e:
            raise RuntimeError(f"setting {self.name}.{variable} = {value!r}: {e}") from e

    def errors(self) -> str:
        """The error and fatal messages it logged (FMI status fmi2Error or fmi2Fatal, or
        such a ``logStatus*`` category), oldest first, each after the instance name."""
        bad = [m for st, c, m in self.log if st in (3, 4) or c in _ERROR_CATEGORIES]
        return "; ".join(f"{self.name}: {m}" for m in bad if m)

    def close(self) -> None:
        if self.fmu is not None:
            if self.live:
                # fmpy raises a bare Exception for any FMI status; a failed instance may
                # refuse to terminate, and is freed all the same
                with contextlib.suppress(Exception):
                    self.fmu.terminate()
                with contextlib.suppress(Exception):
                    self.fmu.freeInstance()  # frees the instance, then the library
                self.live = False
            else:
                with contextlib.suppress(Exception):
                    self.fmu.freeLibrary()
            self.fmu = None
        _LOGGING.pop(self.key, None)
        shutil.rmtree(self.dir, ignore_errors=True)


def reduce(times: list[float], values: list[float], how: str) -> float:
    """``values`` at ``times`` reduced by ``how`` (trapezoidal integral and mean)."""
    if how == "max":
        return max(values)
    if how == "min":
        return min(values)
    if how == "final":
        return values[-1]
    integral = sum(
        0.5 * (values[k] + values[k + 1]) * (times[k + 1] - times[k])
        for k in range(len(values) - 1)
    )
    if how == "integral":
        return integral
    span = times[-1] - times[0]
    return integral / span if span > 0 else values[-1]


def _split(variable: str) -> tuple[str, str]:
    inst, var = variable.split(".", 1)
    return inst, var


def run_case(
    study: Study, case: Case, cache: PackCache, threads: int = 1, host: str | None = None
) -> CaseResult:
    """Run ``case`` of ``study`` to its end time, or to the study's wall-time limit;
    never raises for a failing FMU. ``host`` names the machine and worker (default
    ``<hostname>/serial``)."""
    os.environ["RAYON_NUM_THREADS"] = str(threads)
    start = time.perf_counter()
    result = CaseResult(
        case.key,
        case.index,
        dict(case.values),
        "ok",
        host=host or f"{socket.gethostname()}/serial",
    )
    instances: dict[str, _Instance] = {}
    try:
        _loop(study, case, cache, instances, result, start)
    except CaseTimeout as e:
        result.status = "failed"
        result.diagnostic = str(e)
    except Exception as e:  # noqa: BLE001 - fmpy raises a bare Exception for every FMI error
        result.status = "failed"
        logged = "; ".join(i.errors() for i in instances.values() if i.errors())
        result.diagnostic = logged or f"{type(e).__name__}: {e}"
    finally:
        closing = time.perf_counter()
        for inst in instances.values():
            inst.close()
        result.close_time = time.perf_counter() - closing
    result.wall_time = time.perf_counter() - start
    return result


def _loop(
    study: Study,
    case: Case,
    cache: PackCache,
    instances: dict[str, _Instance],
    result: CaseResult,
    start: float,
) -> None:
    sets = case.scene_sets(study)
    starts: dict[str, dict[str, float]] = {GRANMIX: {}}
    for p in study.partners:
        starts[p.name] = {}
    for p in study.parameters:
        if not p.scene_key:
            inst, var = _split(p.target)
            starts[inst][var] = case.value(p.name)
    # partners first, in the study's order, then granmix (docs/fmu.md)
    order = [p.name for p in study.partners] + [GRANMIX]
    limit = study.wall_time_limit
    h = study.step
    steps = round(study.end_time / h)

    def check_time(done: int) -> None:
        spent = time.perf_counter() - start
        if limit is not None and spent > limit:
            raise CaseTimeout(
                f"wall-time limit of {limit:g} s reached: stopped after {spent:.3g} s, "
                f"at t = {done * h:.6g} s of {study.end_time:g} s ({done} of {steps} steps)"
            )

    began = time.perf_counter()
    sources = {p.name: cache.fmu(p.fmu) for p in study.partners}
    sources[GRANMIX] = cache.fmu(study.scene, sets)
    for name in order:
        # held before it starts, so that a refused start value still frees it
        instances[name] = _Instance(name, sources[name], cache.dir)
        instances[name].start(starts[name])
        check_time(0)
    feeds = {name: [c for c in study.connections if _split(c.target)[0] == name] for name in order}
    watched = sorted({c.source for c in study.connections} | {o.variable for o in study.outputs})
    # the variables each instance's step updates, split once
    reads = {name: [(v, _split(v)[1]) for v in watched if _split(v)[0] == name] for name in order}
    current = {v: instances[_split(v)[0]].get(_split(v)[1]) for v in watched}
    collected = [o.variable for o in study.outputs]
    series: dict[str, list[float]] = {"time": [0.0]}
    for v in collected:
        series[v] = [current[v]]
    result.series = series
    looping = time.perf_counter()
    result.setup_time = looping - began
    try:
        for k in range(steps):
            check_time(k)
            t = k * h
            for name in order:
                inst = instances[name]
                for c in feeds[name]:
                    inst.set(_split(c.target)[1], current[c.source])
                inst.fmu.doStep(currentCommunicationPoint=t, communicationStepSize=h)
                for v, var in reads[name]:
                    current[v] = inst.get(var)
            series["time"].append((k + 1) * h)
            for v in collected:
                series[v].append(current[v])
    finally:
        result.loop_time = time.perf_counter() - looping
    for o in study.outputs:
        for how in o.reduce:
            result.outputs[f"{o.variable}:{how}"] = reduce(series["time"], series[o.variable], how)
