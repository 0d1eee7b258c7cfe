"""`fmpy validate` finds no problem in any FMU the project builds."""

from fmpy.validation import validate_fmu


def test_every_fmu_validates(fmus):
    assert {"barrier", "impact", "panels", "water", "post", "flexible_barrier"} <= set(fmus)
    for name, path in fmus.items():
        problems = validate_fmu(str(path))
        assert problems == [], f"{name}: {problems}"
