"""Checks of a study against its FMUs before any case runs: every scene key is one
granmix accepts, and every connection, FMU parameter and output names a variable of
the right kind that its FMU has. Each failure is a :class:`StudyError` naming the study
key and its line, so that a typo stops the study at once instead of failing every case.
"""

from __future__ import annotations

from pathlib import Path

from fmpy import read_model_description

from granmix.design import Case
from granmix.pack import PackCache, PackError
from granmix.study import GRANMIX, Study, StudyError, locate


def check(study: Study, first: Case | None, cache: PackCache) -> None:
    """Pack the FMUs of the study's first case and hold the study against them."""
    text = Path(study.file).read_text() if study.file else ""

    def fail(key: str, message: str) -> StudyError:
        return StudyError(study.file, key, message, locate(text, key))

    sets = first.scene_sets(study) if first is not None else study.sets
    try:
        paths = {GRANMIX: cache.fmu(study.scene, sets)}
    except PackError as e:
        for i, p in enumerate(study.parameters):
            if p.scene_key and p.scene_key.split(".")[0] in str(e):
                raise fail(f"parameters[{i}].target", f"granmix refuses it: {e}") from e
        key = "study.set" if study.sets and "--set" in str(e) else "study.scene"
        raise fail(key, f"granmix cannot pack the scene: {e}") from e
    for i, p in enumerate(study.partners):
        try:
            paths[p.name] = cache.fmu(p.fmu)
        except PackError as e:
            raise fail(f"partners[{i}].fmu", f"granmix cannot pack it: {e}") from e
    kinds = {
        name: {v.name: v.causality for v in read_model_description(str(path)).modelVariables}
        for name, path in paths.items()
    }

    def need(key: str, variable: str, allowed: tuple[str, ...]) -> None:
        inst, var = variable.split(".", 1)
        kind = kinds[inst].get(var)
        if kind is None:
            raise fail(key, f"FMU `{inst}` has no variable `{var}`")
        if kind not in allowed:
            raise fail(key, f"`{variable}` is an {kind}, not an {' or '.join(allowed)}")

    for i, c in enumerate(study.connections):
        need(f"connections[{i}].from", c.source, ("output",))
        need(f"connections[{i}].to", c.target, ("input",))
    for i, p in enumerate(study.parameters):
        if not p.scene_key:
            need(f"parameters[{i}].target", p.target, ("parameter",))
    for i, o in enumerate(study.outputs):
        need(f"outputs[{i}].variable", o.variable, ("output", "input", "parameter", "local"))
