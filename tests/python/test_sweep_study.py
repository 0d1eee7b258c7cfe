"""Study files and designs of experiments (the `granmix` Python package)."""

import pathlib

import pytest
from conftest import post_coupling
from granmix import StudyError, cases, parse_study

ROOT = pathlib.Path(__file__).resolve().parents[2]

STUDY = (
    """\
[study]
name = "sweep"
scene = "models/scenes/fmu_barrier_2d.toml"
step = 0.001
end_time = 0.05
"""
    + post_coupling()
    + """
[[parameters]]
name = "friction"
target = "scene:materials.0.friction_angle"
values = [25.0, 30.0, 35.0]

[[parameters]]
name = "stiffness"
target = "post.stiffness"
values = [2.0e4, 8.0e4]

[[outputs]]
variable = "granmix.barrier.force.x"
reduce = ["max", "final"]
"""
)


def study(text: str = STUDY):
    return parse_study(text, "study.toml", ROOT)


def error(text: str) -> StudyError:
    with pytest.raises(StudyError) as e:
        study(text)
    return e.value


def test_grid_takes_every_combination_first_parameter_slowest():
    s = study()
    assert [p.name for p in s.partners] == ["post"]
    assert s.parameters[0].scene_key == "materials.0.friction_angle"
    cs = cases(s)
    assert [c.values for c in cs] == [
        (("friction", f), ("stiffness", k)) for f in (25.0, 30.0, 35.0) for k in (2.0e4, 8.0e4)
    ]
    assert len({c.key for c in cs}) == 6
    # the key depends on the case's full specification, not on the run
    assert [c.key for c in cases(study())] == [c.key for c in cs]
    other = cases(study(STUDY.replace("end_time = 0.05", "end_time = 0.06")))
    assert not {c.key for c in other} & {c.key for c in cs}


def lhs(samples: int, seed: int) -> str:
    return (
        STUDY.replace("values = [25.0, 30.0, 35.0]", "range = [20.0, 40.0]").replace(
            "values = [2.0e4, 8.0e4]", "range = [1.0e4, 9.0e4]"
        )
        + f'\n[design]\nkind = "lhs"\nsamples = {samples}\nseed = {seed}\n'
    )


def test_latin_hypercube_puts_one_point_in_every_stratum():
    n = 12
    cs = cases(study(lhs(n, 7)))
    assert len(cs) == n
    for name, (lo, hi) in (("friction", (20.0, 40.0)), ("stiffness", (1.0e4, 9.0e4))):
        strata = sorted(int((c.value(name) - lo) / (hi - lo) * n) for c in cs)
        assert strata == list(range(n)), name
    # seeded: the same points on every machine, other points for another seed
    assert [c.values for c in cases(study(lhs(n, 7)))] == [c.values for c in cs]
    assert [c.values for c in cases(study(lhs(n, 8)))] != [c.values for c in cs]


def test_random_draws_from_values_and_list_takes_the_given_cases():
    s = study(STUDY + '\n[design]\nkind = "random"\nsamples = 20\nseed = 3\n')
    cs = cases(s)
    assert len(cs) == 20
    assert {c.value("friction") for c in cs} <= {25.0, 30.0, 35.0}
    listed = STUDY.replace("values = [25.0, 30.0, 35.0]\n", "").replace(
        "values = [2.0e4, 8.0e4]\n", ""
    )
    listed += (
        '\n[design]\nkind = "list"\ncases = [{friction = 28.0, stiffness = 3.0e4},'
        " {friction = 33.0, stiffness = 5.0e4}]\n"
    )
    assert [c.values for c in cases(study(listed))] == [
        (("friction", 28.0), ("stiffness", 3.0e4)),
        (("friction", 33.0), ("stiffness", 5.0e4)),
    ]


def line_of(text: str, needle: str) -> int:
    return next(i + 1 for i, line in enumerate(text.splitlines()) if needle in line)


@pytest.mark.parametrize(
    ("change", "key", "line_has", "says"),
    [
        (("step = 0.001", "stepp = 0.001"), "study.stepp", "stepp", "unknown key"),
        (('to = "post.force"', 'to = "pole.force"'), "connections[0].to", "pole.force", "no instance"),
        (
            ('target = "post.stiffness"', 'target = "stiffness"'),
            "parameters[1].target",
            'target = "stiffness"',
            "<instance>.<variable>",
        ),
        (('reduce = ["max", "final"]', 'reduce = ["peak"]'), "outputs[0].reduce", "peak", "peak"),
        (
            ('scene = "models/scenes/fmu_barrier_2d.toml"', 'scene = "no_such_scene.toml"'),
            "study.scene",
            "no_such_scene",
            "no file",
        ),
    ],
)
def test_a_bad_study_names_the_key_and_its_line(change, key, line_has, says):
    text = STUDY.replace(*change)
    e = error(text)
    assert e.key == key, str(e)
    assert e.line == line_of(text, line_has), str(e)
    assert says in str(e), str(e)
    assert str(e).startswith(f"study.toml:{e.line}: `{key}`"), str(e)


def test_a_design_with_zero_cases_is_refused():
    e = error(lhs(12, 1).replace("samples = 12", "samples = 0"))
    assert e.key == "design.samples" and "samples ≥ 1" in str(e)
    e = error(STUDY + '\n[design]\nkind = "list"\ncases = []\n')
    assert e.key == "design.cases" and "at least one case" in str(e)


def test_invalid_toml_names_the_line():
    e = error(STUDY.replace('name = "sweep"', 'name = "sweep'))
    assert e.line == 2 and "not valid TOML" in str(e)


def test_scene_overrides_of_every_case_enter_the_case_key():
    base = cases(study())
    text = STUDY.replace("step = 0.001", 'set = ["regions.0.velocity=[2.0, 0.0]"]\nstep = 0.001')
    s = study(text)
    assert s.sets == ("regions.0.velocity=[2.0, 0.0]",)
    assert not {c.key for c in cases(s)} & {c.key for c in base}
    e = error(STUDY.replace("step = 0.001", 'set = ["velocity"]\nstep = 0.001'))
    assert e.key == "study.set" and "key.path=value" in str(e), str(e)


def test_a_repeated_case_has_a_key_of_its_own():
    """An explicit list with a repeat: each case its own key (one Dask task and one row
    each); the first occurrence keeps the key it has without the repeat."""
    listed = STUDY.replace("values = [25.0, 30.0, 35.0]\n", "").replace(
        "values = [2.0e4, 8.0e4]\n", ""
    )
    once = listed + (
        '\n[design]\nkind = "list"\ncases = [{friction = 28.0, stiffness = 3.0e4},'
        " {friction = 33.0, stiffness = 5.0e4}]\n"
    )
    twice = once.replace("5.0e4}]", "5.0e4}, {friction = 28.0, stiffness = 3.0e4}]")
    a, b = cases(study(once)), cases(study(twice))
    assert [c.index for c in b] == [0, 1, 2]
    assert len({c.key for c in b}) == 3
    assert [c.key for c in b[:2]] == [c.key for c in a]
    assert b[2].values == b[0].values


def test_the_wall_time_limit_and_units_are_read_and_do_not_change_the_keys():
    text = STUDY.replace("end_time = 0.05", "end_time = 0.05\nwall_time_limit = 60.0").replace(
        'values = [25.0, 30.0, 35.0]', 'values = [25.0, 30.0, 35.0]\nunit = "deg"'
    )
    s = study(text)
    assert s.wall_time_limit == 60.0 and study().wall_time_limit is None
    assert s.parameters[0].unit == "deg" and s.parameters[1].unit == ""
    assert [c.key for c in cases(s)] == [c.key for c in cases(study())]
    e = error(text.replace("wall_time_limit = 60.0", "wall_time_limit = -1.0"))
    assert e.key == "study.wall_time_limit" and e.line == 6 and "> 0" in str(e), str(e)
    e = error(text.replace('unit = "deg"', "unit = 1"))
    assert e.key == "parameters[0].unit" and "expected a string" in str(e), str(e)
