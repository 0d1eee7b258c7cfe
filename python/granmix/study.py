"""Study files: one granmix scene, its partner FMUs and their connections, the
parameters to vary, the design of experiments and the outputs to collect.

A study file is TOML::

    [study]
    name = "barrier_sweep"
    scene = "../scenes/fmu_barrier_2d.toml"   # relative to the study file
    set = ["regions.0.velocity=[2.0, 0.0]"]   # scene overrides of every case (optional)
    step = 0.001                               # communication step (s)
    end_time = 0.2
    wall_time_limit = 600.0                    # seconds per case (optional)

    [[partners]]
    name = "post"
    fmu = "../structures/post.toml"            # a structure file or any .fmu

    [[connections]]
    from = "granmix.barrier.force.x"
    to = "post.force"

    [[parameters]]
    name = "friction"
    target = "scene:materials.0.friction_angle" # a scene key (--set path) ...
    values = [25.0, 30.0, 35.0]
    unit = "deg"                                # for plots (optional; an FMU's own unit else)

    [[parameters]]
    name = "stiffness"
    target = "post.stiffness"                   # ... or an FMU parameter
    range = [2.0e4, 8.0e4]

    [design]
    kind = "lhs"                                # grid, list, random or lhs
    samples = 12
    seed = 1

    [[outputs]]
    variable = "granmix.barrier.force.x"
    reduce = ["max", "final"]

The granmix FMU's instance is named ``granmix``. Every error names the file, the key
and, where it can be found, the line.
"""

from __future__ import annotations

import math
import re
import tomllib
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

#: The instance name of the granmix FMU in connections, parameters and outputs.
GRANMIX = "granmix"
#: How an output's time series is reduced to one value per case.
REDUCTIONS = ("max", "min", "final", "mean", "integral")
#: Designs of experiments.
DESIGNS = ("grid", "list", "random", "lhs", "ensemble", "refine")
#: The scene keys an ensemble member and a refine level set (the study may not).
MEMBER_KEY = "simulation.perturbation"
LEVEL_KEY = "simulation.dp"
#: The bounds of an ensemble's perturbation ε (a fraction of dp), as granmix checks them.
EPSILON_RANGE = (0.0, 0.5)


class StudyError(ValueError):
    """An error in a study file: the file, the key path and, when known, the line."""

    def __init__(self, file: str, key: str, message: str, line: int | None = None) -> None:
        self.file, self.key, self.line, self.message = file, key, line, message
        at = f"{file}:{line}" if line is not None else file
        super().__init__(f"{at}: `{key}`: {message}" if key else f"{at}: {message}")


@dataclass(frozen=True)
class Partner:
    """A partner FMU: a structure file (packed by ``granmix pack-fmu``) or an .fmu."""

    name: str
    fmu: Path


@dataclass(frozen=True)
class Connection:
    """Output ``source`` of one instance feeds input ``target`` of another."""

    source: str
    target: str


@dataclass(frozen=True)
class Parameter:
    """A varied parameter: a scene key (``scene:<key.path>``) or an FMU parameter
    (``<instance>.<variable>``), with its values (grid, random over ``values``) or its
    range (random, lhs)."""

    name: str
    target: str
    values: tuple[Any, ...] = ()
    range: tuple[float, float] | None = None
    #: The unit shown in plots ("" for the FMU's own unit, or none for a scene key).
    unit: str = ""

    @property
    def scene_key(self) -> str | None:
        """The scene key path of a scene parameter, else None."""
        return self.target[len("scene:") :] if self.target.startswith("scene:") else None


@dataclass(frozen=True)
class Output:
    """An output variable (``<instance>.<variable>``) and its reductions."""

    variable: str
    reduce: tuple[str, ...] = ("final",)
    #: The unit shown in plots ("" for the FMU's own unit).
    unit: str = ""


@dataclass(frozen=True)
class Design:
    kind: str = "grid"
    samples: int = 0
    seed: int = 0
    #: Explicit cases (kind ``list``): parameter name → value.
    cases: tuple[tuple[tuple[str, Any], ...], ...] = ()
    #: Ensemble members per case (1: no ensemble). Member m starts with every soil and
    #: water particle moved by ``epsilon``·dp in directions drawn from seed ``seed + m``
    #: (the scene's ``simulation.perturbation``).
    members: int = 1
    epsilon: float = 1e-6
    #: The particle spacings of a refine design (m), coarsest first.
    levels: tuple[float, ...] = ()

    @property
    def ensemble(self) -> bool:
        """Whether each case of the design is an ensemble of members."""
        return self.members > 1


@dataclass(frozen=True)
class Study:
    file: str
    name: str
    scene: Path
    step: float
    end_time: float
    #: Scene overrides (``key.path=value``) of every case.
    sets: tuple[str, ...] = ()
    partners: tuple[Partner, ...] = ()
    connections: tuple[Connection, ...] = ()
    parameters: tuple[Parameter, ...] = ()
    design: Design = field(default_factory=Design)
    outputs: tuple[Output, ...] = ()
    #: Wall-clock seconds a case may take before it is stopped as a failed row (None:
    #: no limit). It does not enter the case keys: it decides whether a case finishes,
    #: not what it computes.
    wall_time_limit: float | None = None


def load_study(path: str | Path) -> Study:
    """Read and check the study file at ``path``."""
    path = Path(path)
    try:
        text = path.read_text()
    except OSError as e:
        raise StudyError(str(path), "", f"cannot read study file: {e.strerror}") from e
    return parse_study(text, str(path), path.parent)


def parse_study(text: str, file: str, base: Path) -> Study:
    """Parse and check study ``text`` (from ``file``; relative paths from ``base``)."""
    try:
        doc = tomllib.loads(text)
    except tomllib.TOMLDecodeError as e:
        line = _decode_line(str(e))
        raise StudyError(file, "", f"not valid TOML: {e}", line) from e
    return _Reader(text, file, base).study(doc)


def _decode_line(message: str) -> int | None:
    m = re.search(r"line (\d+)", message)
    return int(m.group(1)) if m else None


class _Reader:
    """Checks each table of a study document, naming the key and its line."""

    def __init__(self, text: str, file: str, base: Path) -> None:
        self.text, self.file, self.base = text, file, base

    def fail(self, key: str, message: str) -> StudyError:
        return StudyError(self.file, key, message, locate(self.text, key))

    def table(self, value: Any, key: str, allowed: set[str], required: set[str]) -> dict:
        if not isinstance(value, dict):
            raise self.fail(key, "expected a table")
        for k in value:
            if k not in allowed:
                raise self.fail(f"{key}.{k}", f"unknown key; expected one of {sorted(allowed)}")
        for k in sorted(required - value.keys()):
            raise self.fail(key, f"missing key `{k}`")
        return value

    def tables(self, doc: dict, name: str) -> list[dict]:
        v = doc.get(name, [])
        if not isinstance(v, list):
            raise self.fail(name, f"expected [[{name}]] tables")
        return v

    def number(self, v: Any, key: str, positive: bool = True) -> float:
        if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v):
            raise self.fail(key, f"expected a finite number, found {v!r}")
        if positive and v <= 0:
            raise self.fail(key, f"must be > 0, found {v!r}")
        return float(v)

    def variable(self, v: Any, key: str, instances: set[str]) -> str:
        if not isinstance(v, str) or "." not in v:
            raise self.fail(key, f"expected `<instance>.<variable>`, found {v!r}")
        inst = v.split(".", 1)[0]
        if inst not in instances:
            raise self.fail(key, f"no instance `{inst}`; the instances are {sorted(instances)}")
        return v

    def study(self, doc: dict) -> Study:
        top = {"study", "partners", "connections", "parameters", "design", "outputs"}
        for k in doc:
            if k not in top:
                raise self.fail(k, f"unknown table; expected one of {sorted(top)}")
        if "study" not in doc:
            raise self.fail("study", "missing table [study]")
        s = self.table(
            doc["study"],
            "study",
            {"name", "scene", "set", "step", "end_time", "wall_time_limit"},
            {"scene", "step", "end_time"},
        )
        sets = s.get("set", [])
        if not isinstance(sets, list) or not all(
            isinstance(x, str) and re.fullmatch(r"[A-Za-z_][\w.]*=.+", x) for x in sets
        ):
            raise self.fail("study.set", 'expected a list of "key.path=value" overrides')
        scene = self.path(s["scene"], "study.scene", must_exist=True)
        step = self.number(s["step"], "study.step")
        end = self.number(s["end_time"], "study.end_time")
        if end < step:
            raise self.fail("study.end_time", f"shorter than one step ({step} s)")
        limit = None
        if "wall_time_limit" in s:
            limit = self.number(s["wall_time_limit"], "study.wall_time_limit")
        partners = self.partners(doc)
        instances = {GRANMIX} | {p.name for p in partners}
        connections = self.connections(doc, instances)
        parameters = self.parameters(doc, instances)
        design = self.design(doc, parameters)
        for fixed, by in ((MEMBER_KEY, design.ensemble), (LEVEL_KEY, bool(design.levels))):
            for x in sets:
                key = x.split("=", 1)[0].strip()
                if by and (key == fixed or key.startswith(fixed + ".")):
                    raise StudyError(
                        self.file,
                        "study.set",
                        f"`{x}`: `{fixed}` is set by the design ({design.kind}) for every case",
                        locate_item(self.text, "study.set", x),
                    )
        outputs = self.outputs(doc, instances)
        return Study(
            file=self.file,
            name=str(s.get("name", Path(self.file).stem)),
            scene=scene,
            step=step,
            end_time=end,
            sets=tuple(sets),
            partners=partners,
            connections=connections,
            parameters=parameters,
            design=design,
            outputs=outputs,
            wall_time_limit=limit,
        )

    def path(self, v: Any, key: str, must_exist: bool) -> Path:
        if not isinstance(v, str) or not v:
            raise self.fail(key, f"expected a file path, found {v!r}")
        p = (self.base / v).resolve()
        if must_exist and not p.is_file():
            raise self.fail(key, f"no file {p}")
        return p

    def partners(self, doc: dict) -> tuple[Partner, ...]:
        out: list[Partner] = []
        for i, t in enumerate(self.tables(doc, "partners")):
            key = f"partners[{i}]"
            t = self.table(t, key, {"name", "fmu"}, {"name", "fmu"})
            name = t["name"]
            if not isinstance(name, str) or not re.fullmatch(r"[A-Za-z_][A-Za-z0-9_]*", name):
                raise self.fail(f"{key}.name", f"expected an identifier, found {name!r}")
            if name == GRANMIX or any(p.name == name for p in out):
                raise self.fail(f"{key}.name", f"instance name `{name}` is taken")
            fmu = self.path(t["fmu"], f"{key}.fmu", must_exist=True)
            if fmu.suffix not in (".fmu", ".toml"):
                raise self.fail(f"{key}.fmu", "expected an .fmu or a structure .toml")
            out.append(Partner(name, fmu))
        return tuple(out)

    def connections(self, doc: dict, instances: set[str]) -> tuple[Connection, ...]:
        out: list[Connection] = []
        for i, t in enumerate(self.tables(doc, "connections")):
            key = f"connections[{i}]"
            t = self.table(t, key, {"from", "to"}, {"from", "to"})
            src = self.variable(t["from"], f"{key}.from", instances)
            dst = self.variable(t["to"], f"{key}.to", instances)
            if src.split(".", 1)[0] == dst.split(".", 1)[0]:
                raise self.fail(f"{key}.to", "connects an instance to itself")
            if any(c.target == dst for c in out):
                raise self.fail(f"{key}.to", f"`{dst}` already has a source")
            out.append(Connection(src, dst))
        return tuple(out)

    def parameters(self, doc: dict, instances: set[str]) -> tuple[Parameter, ...]:
        out: list[Parameter] = []
        for i, t in enumerate(self.tables(doc, "parameters")):
            key = f"parameters[{i}]"
            t = self.table(
                t, key, {"name", "target", "values", "range", "unit"}, {"name", "target"}
            )
            name = t["name"]
            if not isinstance(name, str) or not name or any(p.name == name for p in out):
                raise self.fail(f"{key}.name", f"expected a new parameter name, found {name!r}")
            target = t["target"]
            if not isinstance(target, str):
                raise self.fail(f"{key}.target", f"expected a string, found {target!r}")
            if target.startswith("scene:"):
                if not re.fullmatch(r"scene:[A-Za-z_][\w]*(\.[\w]+)*", target):
                    raise self.fail(f"{key}.target", "expected `scene:<key.path>`")
            else:
                self.variable(target, f"{key}.target", instances)
            values: tuple[Any, ...] = ()
            if "values" in t:
                v = t["values"]
                if not isinstance(v, list) or not v:
                    raise self.fail(f"{key}.values", "expected a non-empty list")
                values = tuple(v)
            rng = None
            if "range" in t:
                r = t["range"]
                if not isinstance(r, list) or len(r) != 2:
                    raise self.fail(f"{key}.range", "expected [low, high]")
                lo = self.number(r[0], f"{key}.range", positive=False)
                hi = self.number(r[1], f"{key}.range", positive=False)
                if not lo < hi:
                    raise self.fail(f"{key}.range", f"low {lo} must be below high {hi}")
                rng = (lo, hi)
            if values and rng:
                raise self.fail(key, "give `values` or `range`, not both")
            out.append(Parameter(name, target, values, rng, self.unit(t, key)))
        return tuple(out)

    def design(self, doc: dict, params: tuple[Parameter, ...]) -> Design:
        t = self.table(
            doc.get("design", {}),
            "design",
            {"kind", "samples", "seed", "cases", "members", "epsilon", "levels"},
            set(),
        )
        kind = t.get("kind", "grid")
        if kind not in DESIGNS:
            raise self.fail("design.kind", f"unknown design `{kind}`; use one of {list(DESIGNS)}")
        seed = t.get("seed", 0)
        if isinstance(seed, bool) or not isinstance(seed, int) or seed < 0:
            raise self.fail("design.seed", f"expected an integer ≥ 0, found {seed!r}")
        samples = t.get("samples", 0)
        if kind in ("random", "lhs"):
            if isinstance(samples, bool) or not isinstance(samples, int) or samples < 1:
                raise self.fail("design.samples", f"a {kind} design needs samples ≥ 1")
        elif "samples" in t:
            raise self.fail("design.samples", f"a {kind} design takes no samples")
        cases: tuple[tuple[tuple[str, Any], ...], ...] = ()
        names = [p.name for p in params]
        if kind == "list":
            rows = t.get("cases", [])
            if not isinstance(rows, list) or not rows:
                raise self.fail("design.cases", "a list design needs at least one case")
            parsed = []
            for k, row in enumerate(rows):
                if not isinstance(row, dict) or set(row) != set(names):
                    raise self.fail(f"design.cases[{k}]", f"expected a value for each of {names}")
                parsed.append(tuple((n, row[n]) for n in names))
            cases = tuple(parsed)
        elif "cases" in t:
            raise self.fail("design.cases", f"a {kind} design takes no cases")
        for i, p in enumerate(params):
            key = f"parameters[{i}]"
            if kind == "grid" and not p.values:
                raise self.fail(key, "a grid design needs `values` for every parameter")
            if kind == "lhs" and p.range is None:
                raise self.fail(key, "a Latin hypercube design needs `range` for every parameter")
            if kind == "random" and not (p.values or p.range):
                raise self.fail(key, "a random design needs `values` or `range`")
        if kind in ("grid", "random", "lhs") and not params:
            raise self.fail("parameters", f"a {kind} design varies at least one parameter")
        if kind in ("ensemble", "refine"):
            for i, p in enumerate(params):
                if not p.values:
                    raise self.fail(
                        f"parameters[{i}]",
                        f"the parameters of a {kind} design form a grid: give `values`",
                    )
        members = self.members(t, kind)
        epsilon = self.epsilon(t, members)
        levels = self.levels(t, kind)
        for i, p in enumerate(params):
            for column, by in (("member", members > 1), ("dp", bool(levels))):
                if by and p.name == column:
                    raise self.fail(
                        f"parameters[{i}].name",
                        f"`{column}` names the design's own column ({kind}); rename the parameter",
                    )
        for i, p in enumerate(params):
            key = p.scene_key or ""
            for fixed, by in ((MEMBER_KEY, members > 1), (LEVEL_KEY, bool(levels))):
                if by and (key == fixed or key.startswith(fixed + ".")):
                    raise self.fail(
                        f"parameters[{i}].target",
                        f"`{fixed}` is set by the design ({kind}) for every case",
                    )
        return Design(kind, samples, seed, cases, members, epsilon, levels)

    def members(self, t: dict, kind: str) -> int:
        if "members" not in t:
            if kind in ("ensemble", "refine"):
                raise self.fail("design", f"a {kind} design needs `members` (≥ 2)")
            return 1
        n = t["members"]
        if isinstance(n, bool) or not isinstance(n, int) or n < 2:
            raise self.fail(
                "design.members",
                f"an ensemble needs an integer number of members ≥ 2, found {n!r} (a spread "
                "needs two draws; 8 or more for a 95th percentile)",
            )
        return n

    def epsilon(self, t: dict, members: int) -> float:
        if "epsilon" not in t:
            return Design.epsilon
        if members < 2:
            raise self.fail("design.epsilon", "perturbs ensemble members: give `members` ≥ 2")
        e = self.number(t["epsilon"], "design.epsilon", positive=False)
        lo, hi = EPSILON_RANGE
        if not lo < e < hi:
            raise self.fail(
                "design.epsilon",
                f"must lie in ({lo:g}, {hi:g}): the distance each particle moves, as a "
                f"fraction of dp (default 1e-6; 1e-12 is a round-off-level change), found {e!r}",
            )
        return e

    def levels(self, t: dict, kind: str) -> tuple[float, ...]:
        if kind != "refine":
            if "levels" in t:
                raise self.fail("design.levels", f"a {kind} design takes no levels (refine does)")
            return ()
        v = t.get("levels")
        if not isinstance(v, list) or len(v) < 2:
            raise self.fail(
                "design.levels",
                "a refine design needs a list of at least two particle spacings dp (m), "
                "e.g. [0.04, 0.02, 0.01]; three give an observed order",
            )
        levels = [self.number(x, "design.levels") for x in v]
        if len(set(levels)) != len(levels):
            raise self.fail("design.levels", f"repeats a level: {levels}")
        return tuple(sorted(levels, reverse=True))

    def outputs(self, doc: dict, instances: set[str]) -> tuple[Output, ...]:
        out: list[Output] = []
        for i, t in enumerate(self.tables(doc, "outputs")):
            key = f"outputs[{i}]"
            t = self.table(t, key, {"variable", "reduce", "unit"}, {"variable"})
            var = self.variable(t["variable"], f"{key}.variable", instances)
            red = t.get("reduce", ["final"])
            if not isinstance(red, list) or not red:
                raise self.fail(f"{key}.reduce", "expected a non-empty list")
            for r in red:
                if r not in REDUCTIONS:
                    raise self.fail(f"{key}.reduce", f"unknown reduction {r!r}; use {REDUCTIONS}")
            out.append(Output(var, tuple(red), self.unit(t, key)))
        return tuple(out)

    def unit(self, t: dict, key: str) -> str:
        u = t.get("unit", "")
        if not isinstance(u, str):
            raise self.fail(f"{key}.unit", f"expected a string, found {u!r}")
        return u


def locate_item(text: str, key: str, item: str) -> int | None:
    """The 1-based line of the array element ``item`` (a string) of ``key`` in study
    ``text`` (an array written over several lines), else the line of ``key``."""
    first = locate(text, key)
    if first is None:
        return None
    lines = text.splitlines()
    quoted = (f'"{item}"', f"'{item}'")
    for n in range(first - 1, len(lines)):
        if any(q in lines[n] for q in quoted):
            return n + 1
        if n > first - 1 and re.match(r"\s*(\[|[A-Za-z_][\w]*\s*=)", lines[n]):
            break
    return first


def locate(text: str, key: str) -> int | None:
    """The 1-based line of ``key`` (``study.step``, ``parameters[1].target``,
    ``design.cases[0]``) in study ``text``: its table header, then the key's line within
    that table; the deepest part found."""
    parts = re.findall(r"([A-Za-z_]\w*)(?:\[(\d+)\])?", key)
    if not parts:
        return None
    lines = text.splitlines()
    name, index = parts[0][0], int(parts[0][1] or 0)
    header = None
    count = 0
    for n, line in enumerate(lines):
        s = line.strip()
        if s in (f"[[{name}]]", f"[{name}]"):
            if count == index or s == f"[{name}]":
                header = n
                break
            count += 1
    if header is None:
        return None
    if len(parts) == 1:
        return header + 1
    sub = parts[1][0]
    for n in range(header + 1, len(lines)):
        s = lines[n].strip()
        if s.startswith("["):
            break
        if re.match(rf"{re.escape(sub)}\s*=", s):
            return n + 1
    return header + 1
