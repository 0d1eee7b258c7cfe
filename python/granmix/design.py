"""Designs of experiments: the cases of a study.

- ``grid``: every combination of the parameters' ``values``, the first parameter
  varying slowest;
- ``list``: the study's explicit ``design.cases``;
- ``random``: ``samples`` draws, uniform over each parameter's ``range`` or over its
  ``values``;
- ``lhs``: a Latin hypercube of ``samples`` points over the ranges: each parameter's
  range cut into ``samples`` equal strata, one point in each, the strata paired at random.

Random designs draw from ``numpy.random.default_rng(seed)`` in a fixed order, so a study
gives the same cases on every machine. Each case is keyed by a hash of its full
specification (study settings, partner files and parameter values), which ``--resume``
and the result table use to find it again. A design may hold the same values more than
once (an explicit list with a repeat): the n-th repeat's specification carries
``repeat = n``, so every case has a key of its own and a row of its own.
"""

from __future__ import annotations

import hashlib
import itertools
import json
from dataclasses import dataclass
from typing import Any

import numpy as np

from granmix.study import LEVEL_KEY, MEMBER_KEY, Design, Study

#: The case values a design adds: the ensemble member's index, the refine level's dp.
MEMBER = "member"
LEVEL = "dp"


@dataclass(frozen=True)
class Case:
    """One co-simulation of a study: its index, parameter values and key, and the scene
    overrides its design adds (an ensemble member's perturbation, a refine level's dp)."""

    index: int
    values: tuple[tuple[str, Any], ...]
    key: str
    design_sets: tuple[str, ...] = ()

    def value(self, name: str) -> Any:
        return dict(self.values)[name]

    def scene_sets(self, study: Study) -> tuple[str, ...]:
        """The ``--set`` overrides of this case's granmix FMU: the study's fixed ones,
        each scene parameter's value, then the design's own."""
        return (
            study.sets
            + tuple(f"{p.scene_key}={self.value(p.name)}" for p in study.parameters if p.scene_key)
            + self.design_sets
        )


def member_sets(design: Design, member: int) -> tuple[str, ...]:
    """The scene overrides of ensemble member ``member``: the seed ``seed + member`` and
    the distance ε (granmix's ``simulation.perturbation``)."""
    return (
        f"{MEMBER_KEY}.seed={design.seed + member}",
        f"{MEMBER_KEY}.amplitude={design.epsilon!r}",
    )


def cases(study: Study) -> list[Case]:
    """The cases of ``study``'s design, in design order: each base case (a refine
    design's levels, coarsest first, then its parameters' grid), then its members."""
    names = [p.name for p in study.parameters]
    d = study.design
    rows = _rows(study)
    levels: tuple[float | None, ...] = d.levels or (None,)
    members = range(d.members) if d.ensemble else (None,)
    base = _fingerprint(study)
    out = []
    seen: dict[str, int] = {}
    for level in levels:
        for row in rows:
            for m in members:
                values = tuple(zip(names, row, strict=True))
                sets: tuple[str, ...] = ()
                if level is not None:
                    values += ((LEVEL, level),)
                    sets += (f"{LEVEL_KEY}={level!r}",)
                if m is not None:
                    values += ((MEMBER, m),)
                    sets += member_sets(d, m)
                spec: dict[str, Any] = {"study": base, "values": values}
                if sets:
                    spec["sets"] = sets
                text = json.dumps(spec, sort_keys=True, default=str)
                repeat = seen.get(text, 0)
                seen[text] = repeat + 1
                if repeat:
                    # a repeat of an earlier case: the same specification, counted
                    spec["repeat"] = repeat
                    text = json.dumps(spec, sort_keys=True, default=str)
                key = hashlib.sha256(text.encode()).hexdigest()[:16]
                out.append(Case(len(out), values, key, sets))
    return out


def _rows(study: Study) -> list[tuple[Any, ...]]:
    """The parameter values of each base case of the design."""
    d = study.design
    if d.kind in ("grid", "ensemble", "refine"):
        return [tuple(r) for r in itertools.product(*(p.values for p in study.parameters))]
    if d.kind == "list":
        return [tuple(v for _, v in row) for row in d.cases]
    if d.kind == "random":
        rng = np.random.default_rng(d.seed)
        return [
            tuple(_draw(rng, p.values, p.range) for p in study.parameters)
            for _ in range(d.samples)
        ]
    return _latin_hypercube(study, np.random.default_rng(d.seed))


def _draw(rng: np.random.Generator, values: tuple[Any, ...], rng_range: Any) -> Any:
    if rng_range is not None:
        lo, hi = rng_range
        return float(lo + (hi - lo) * rng.random())
    return values[int(rng.integers(len(values)))]


def _latin_hypercube(study: Study, rng: np.random.Generator) -> list[tuple[float, ...]]:
    n = study.design.samples
    columns = []
    for p in study.parameters:
        lo, hi = p.range  # checked by the study reader
        strata = rng.permutation(n)
        u = (strata + rng.random(n)) / n
        columns.append([float(lo + (hi - lo) * x) for x in u])
    return [tuple(c[i] for c in columns) for i in range(n)]


def _fingerprint(study: Study) -> dict[str, Any]:
    """What, besides the parameter values, decides a case's result."""
    return {
        "scene": _digest(study.scene),
        "sets": list(study.sets),
        "step": study.step,
        "end_time": study.end_time,
        "partners": [(p.name, _digest(p.fmu)) for p in study.partners],
        "connections": [(c.source, c.target) for c in study.connections],
        "targets": [(p.name, p.target) for p in study.parameters],
    }


def _digest(path: Any) -> str:
    return hashlib.sha256(path.read_bytes()).hexdigest()
