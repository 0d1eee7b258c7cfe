"""Checks of a study against its FMUs before any case runs: the study's scene overrides
(``study.set``) and every scene parameter are keys granmix accepts, and every
connection, FMU parameter and output names a variable of the right kind that its FMU
has. Each failure is a :class:`StudyError` naming the study key and its line, so that a
typo stops the study at once instead of failing every case.

:func:`variables` lists each instance's variables (name, causality, unit, start value,
description): ``granmix-sweep --variables STUDY`` prints them.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

from fmpy import read_model_description

from granmix.design import LEVEL, Case
from granmix.pack import PackCache, PackError
from granmix.study import GRANMIX, Study, StudyError, locate, locate_item


@dataclass(frozen=True)
class Variable:
    """One FMU variable as a study names it (``<instance>.<name>``)."""

    name: str
    causality: str
    unit: str
    start: str
    description: str


def _read(path: Path) -> dict[str, Variable]:
    out = {}
    for v in read_model_description(str(path)).modelVariables:
        unit = v.unit or (v.declaredType.unit if v.declaredType is not None else None) or ""
        start = "" if v.start is None else str(v.start)
        out[v.name] = Variable(v.name, str(v.causality), unit, start, v.description or "")
    return out


def _text(study: Study) -> str:
    try:
        return Path(study.file).read_text() if study.file else ""
    except OSError:
        return ""


def _pack_scene(study: Study, first: Case | None, cache: PackCache) -> Path:
    """The granmix FMU of the first case; a refusal is pinned on the study key that
    carries the refused override: ``study.set`` (and the line of the refused entry),
    else the scene parameter, else ``study.scene``."""
    text = _text(study)

    def fail(key: str, message: str, line: int | None) -> StudyError:
        return StudyError(study.file, key, message, line)

    sets = first.scene_sets(study) if first is not None else study.sets
    try:
        return cache.fmu(study.scene, sets)
    except PackError as e:
        refused = e
    # which override granmix refuses: the study's own ones alone, then each one alone,
    # then each scene parameter on top of them (packing only on this error path)
    if study.sets:
        try:
            cache.fmu(study.scene, study.sets)
        except PackError as e:
            for item in study.sets:
                try:
                    cache.fmu(study.scene, (item,))
                except PackError as one:
                    line = locate_item(text, "study.set", item)
                    raise fail("study.set", f"granmix refuses `{item}`: {one}", line) from one
            line = locate(text, "study.set")
            raise fail("study.set", f"granmix refuses these overrides: {e}", line) from e
    if first is not None:
        for i, p in enumerate(study.parameters):
            if not p.scene_key:
                continue
            try:
                cache.fmu(study.scene, (*study.sets, f"{p.scene_key}={first.value(p.name)}"))
            except PackError as e:
                key = f"parameters[{i}].target"
                raise fail(key, f"granmix refuses it: {e}", locate(text, key)) from e
    if first is not None and first.design_sets:
        key = "design.levels" if study.design.levels else "design.epsilon"
        raise fail(
            key,
            f"granmix refuses the design's overrides {list(first.design_sets)}: {refused}",
            locate(text, key) or locate(text, "design"),
        ) from refused
    raise fail(
        "study.scene", f"granmix cannot pack the scene: {refused}", locate(text, "study.scene")
    ) from refused


def _check_levels(study: Study, design: list[Case], cache: PackCache) -> None:
    """Pack the first case of every refine level after the first: a level granmix
    refuses (a dp too coarse for a region to hold a particle) stops the study."""
    seen = {design[0].value(LEVEL)} if design else set()
    text = _text(study)
    for c in design:
        level = c.value(LEVEL)
        if level in seen:
            continue
        seen.add(level)
        try:
            cache.fmu(study.scene, c.scene_sets(study))
        except PackError as e:
            raise StudyError(
                study.file,
                "design.levels",
                f"granmix refuses level dp = {level:g} m: {e}",
                locate(text, "design.levels"),
            ) from e


def variables(study: Study, first: Case | None, cache: PackCache) -> dict[str, dict[str, Variable]]:
    """Each instance's variables (the granmix FMU of the first case, then the partners),
    packing the FMUs that are not in ``cache`` yet."""
    text = _text(study)
    paths = {GRANMIX: _pack_scene(study, first, cache)}
    for i, p in enumerate(study.partners):
        try:
            paths[p.name] = cache.fmu(p.fmu)
        except PackError as e:
            key = f"partners[{i}].fmu"
            raise StudyError(
                study.file, key, f"granmix cannot pack it: {e}", locate(text, key)
            ) from e
    return {name: _read(path) for name, path in paths.items()}


def check(
    study: Study, first: Case | None, cache: PackCache, design: list[Case] | None = None
) -> dict[str, dict[str, Variable]]:
    """Pack the FMUs of the study's first case (and of the first case of each refine
    level in ``design``), hold the study against them, and return each instance's
    variables."""
    text = _text(study)

    def fail(key: str, message: str) -> StudyError:
        return StudyError(study.file, key, message, locate(text, key))

    found = variables(study, first, cache)
    if study.design.levels and design:
        _check_levels(study, design, cache)

    def need(key: str, variable: str, allowed: tuple[str, ...]) -> None:
        inst, var = variable.split(".", 1)
        v = found[inst].get(var)
        if v is None:
            raise fail(
                key,
                f"FMU `{inst}` has no variable `{var}` "
                "(`granmix-sweep --variables STUDY` lists them)",
            )
        if v.causality not in allowed:
            raise fail(key, f"`{variable}` is an {v.causality}, not an {' or '.join(allowed)}")

    for i, c in enumerate(study.connections):
        need(f"connections[{i}].from", c.source, ("output",))
        need(f"connections[{i}].to", c.target, ("input",))
    for i, p in enumerate(study.parameters):
        if not p.scene_key:
            need(f"parameters[{i}].target", p.target, ("parameter",))
    for i, o in enumerate(study.outputs):
        need(f"outputs[{i}].variable", o.variable, ("output", "input", "parameter", "local"))
    return found


def units(study: Study, found: dict[str, dict[str, Variable]]) -> dict[str, str]:
    """The unit of each parameter (by name) and each output variable: the study's
    ``unit``, else the FMU's, else ""."""
    out: dict[str, str] = {}
    for p in study.parameters:
        unit = p.unit
        if not unit and not p.scene_key:
            inst, var = p.target.split(".", 1)
            v = found.get(inst, {}).get(var)
            unit = v.unit if v else ""
        out[p.name] = unit
    for o in study.outputs:
        inst, var = o.variable.split(".", 1)
        v = found.get(inst, {}).get(var)
        out[o.variable] = o.unit or (v.unit if v else "")
    return out
