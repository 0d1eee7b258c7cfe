"""Ensembles and refine designs: members perturbed by granmix's seeded start, their
statistics against numpy, the envelope plots, reproducible members, and the convergence
verdict against analytic sequences."""

import math
import pathlib

import numpy as np
import pandas as pd
import pytest
from granmix.cli import main
from granmix.design import cases
from granmix.ensemble import observed_order
from granmix.master import run_case
from granmix.pack import PackCache
from granmix.store import column_unit
from granmix.study import StudyError, parse_study

ROOT = pathlib.Path(__file__).resolve().parents[2]
SCENE = ROOT / "models" / "scenes" / "debris_flow_saturated.toml"

OUTPUTS = """
[[outputs]]
variable = "granmix.barrier.force_grains.x"
reduce = ["max", "integral"]

[[outputs]]
variable = "granmix.barrier.force_water.x"
reduce = ["max", "integral"]

[[outputs]]
variable = "granmix.boulder_1.force.x"
reduce = ["max", "integral"]
"""


#: The barrier moved up the slope against the slab's toe, so that a short run loads it.
NEAR = (
    '"barriers.0.shape.min=[2.05, 0.85]", "barriers.0.shape.max=[2.15, 1.4]", '
    '"barriers.0.reference_point=[2.05, 0.85]"'
)


def ensemble_study(members: int, end: float = 0.2, extra: str = "") -> str:
    return f"""\
[study]
name = "debris_ensemble"
scene = "{SCENE}"
set = ["simulation.end_time={end}", {NEAR}]
step = 0.01
end_time = {end}

[design]
kind = "ensemble"
members = {members}
{extra}
{OUTPUTS}"""


def write(tmp: pathlib.Path, text: str) -> pathlib.Path:
    p = tmp / "study.toml"
    p.write_text(text)
    return p


@pytest.fixture(scope="module")
def eight(tmp_path_factory):
    """An ensemble of 8 members of the bundled saturated debris flow, 0.2 s, serial."""
    d = tmp_path_factory.mktemp("ensemble")
    assert main([str(write(d, ensemble_study(8))), "--out", str(d / "out"), "--serial", "--quiet"]) == 0
    return d / "out"


def test_the_statistics_are_the_members_mean_sd_min_max_and_p95(eight):
    rows = pd.read_parquet(eight / "results.parquet")
    stats = pd.read_parquet(eight / "ensemble.parquet")
    assert (rows["status"] == "ok").all() and sorted(rows["member"]) == list(range(8))
    for variable in ("barrier.force_grains.x", "barrier.force_water.x", "boulder_1.force.x"):
        for how in ("max", "integral"):
            col = f"granmix.{variable}:{how}"
            x = rows[col].to_numpy()
            s = stats[stats["output"] == col].iloc[0]
            assert s["members"] == 8 and s["failed"] == 0
            assert s["mean"] == pytest.approx(x.mean(), rel=1e-12, abs=1e-300)
            assert s["sd"] == pytest.approx(x.std(ddof=1), rel=1e-12, abs=1e-300)
            assert (s["min"], s["max"]) == (x.min(), x.max())
            # the empirical 95th percentile of 8: between the 7th and 8th order statistic
            o = np.sort(x)
            assert s["p95"] == pytest.approx(o[6] + 0.65 * (o[7] - o[6]), rel=1e-12, abs=1e-300)
    # the barrier is loaded; members differ (the start is perturbed), by far less than
    # the load itself over this short run
    for col in ("barrier.force_grains.x:max", "barrier.force_water.x:integral"):
        s = stats[stats["output"] == f"granmix.{col}"].iloc[0]
        assert s["mean"] > 10 and 0 < s["sd"] < 0.05 * s["mean"], s.to_dict()


def test_an_impulse_is_reported_in_the_loads_unit_times_seconds():
    units = {"granmix.barrier.force_grains.x": "N/m", "post.displacement": ""}
    assert column_unit("granmix.barrier.force_grains.x:integral", units) == "N·s/m"
    assert column_unit("granmix.barrier.force_grains.x:max", units) == "N/m"
    assert column_unit("post.displacement:integral", units) == "s"
    assert column_unit("post.force:integral", {"post.force": "N"}) == "N·s"
    assert column_unit("post.displacement:final", units) == ""


def test_every_load_has_an_envelope_plot(eight):
    for variable in ("barrier.force_grains.x", "barrier.force_water.x", "boulder_1.force.x"):
        png = eight / "plots" / f"envelope__granmix.{variable}.png"
        assert png.stat().st_size > 10_000, png


def test_a_member_rerun_alone_is_bitwise_the_ensembles(eight, tmp_path):
    study = parse_study(ensemble_study(8), str(tmp_path / "s.toml"), tmp_path)
    member = cases(study)[5]
    r = run_case(study, member, PackCache(tmp_path / "fmus"))
    row = pd.read_parquet(eight / "results.parquet").set_index("member").loc[5]
    assert r.key == row["key"]
    for col, v in r.outputs.items():
        assert v == row[col], col
    series = pd.read_parquet(eight / "series.parquet")
    mine = series[series["key"] == r.key]
    assert mine["granmix.boulder_1.force.x"].tolist() == r.series["granmix.boulder_1.force.x"]


def test_two_workers_give_the_serial_members_bitwise(tmp_path):
    text = ensemble_study(3, end=0.05)
    a, b = tmp_path / "a", tmp_path / "b"
    assert main([str(write(tmp_path, text)), "--out", str(a), "--serial", "--quiet"]) == 0
    assert main([str(write(tmp_path, text)), "--out", str(b), "--workers", "2", "--quiet"]) == 0
    ta = pd.read_parquet(a / "ensemble.parquet")
    tb = pd.read_parquet(b / "ensemble.parquet")
    pd.testing.assert_frame_equal(ta, tb, check_exact=True)
    sa = pd.read_parquet(a / "series.parquet").sort_values(["key", "time"], ignore_index=True)
    sb = pd.read_parquet(b / "series.parquet").sort_values(["key", "time"], ignore_index=True)
    pd.testing.assert_frame_equal(sa, sb, check_exact=True)


@pytest.mark.parametrize(
    ("design", "key", "words"),
    [
        ('kind = "ensemble"\nmembers = 1', "design.members", "≥ 2"),
        ('kind = "ensemble"', "design", "needs `members`"),
        ('kind = "ensemble"\nmembers = 4\nepsilon = 0.0', "design.epsilon", "(0, 0.5)"),
        ('kind = "ensemble"\nmembers = 4\nepsilon = 0.5', "design.epsilon", "(0, 0.5)"),
        ('kind = "ensemble"\nmembers = 4\nepsilon = -1e-6', "design.epsilon", "(0, 0.5)"),
        ('kind = "refine"\nmembers = 4', "design.levels", "at least two"),
        ('kind = "refine"\nmembers = 4\nlevels = [0.02, 0.02]', "design.levels", "repeats"),
        ('kind = "refine"\nmembers = 1\nlevels = [0.04, 0.02]', "design.members", "≥ 2"),
        ('kind = "ensemble"\nmembers = 3\nlevels = [0.04, 0.02]', "design.levels", "takes no levels"),
    ],
)
def test_bad_designs_name_the_key_and_its_line(tmp_path, design, key, words):
    text = f'[study]\nscene = "{SCENE}"\nstep = 0.01\nend_time = 0.1\n\n[design]\n{design}\n'
    with pytest.raises(StudyError) as e:
        parse_study(text, "study.toml", tmp_path)
    assert e.value.key == key and words in e.value.message, str(e.value)
    assert e.value.line is not None and e.value.line >= 6, str(e.value)


def test_a_refine_level_too_coarse_for_the_scene_is_refused_by_name(tmp_path, capsys):
    text = ensemble_study(2, end=0.02).replace(
        'kind = "ensemble"', 'kind = "refine"\nlevels = [0.5, 0.02]'
    )
    assert main([str(write(tmp_path, text)), "--out", str(tmp_path / "out"), "--serial", "--quiet"]) == 2
    err = capsys.readouterr().err
    assert "design.levels" in err and "dp = 0.5" in err and "holds no particle" in err, err


def test_the_design_owns_the_perturbation_and_the_level(tmp_path):
    text = ensemble_study(2).replace(
        f'set = ["simulation.end_time=0.2", {NEAR}]',
        f'set = ["simulation.end_time=0.2", {NEAR}, "simulation.perturbation.seed=3"]',
    )
    with pytest.raises(StudyError, match="set by the design"):
        parse_study(text, "study.toml", tmp_path)


def test_members_differ_by_seed_alone_and_refine_levels_come_coarsest_first(tmp_path):
    text = ensemble_study(3).replace(
        'kind = "ensemble"', 'kind = "refine"\nlevels = [0.02, 0.04]\nseed = 10'
    )
    study = parse_study(text, "study.toml", tmp_path)
    cs = cases(study)
    assert [(c.value("dp"), c.value("member")) for c in cs] == [
        (0.04, 0), (0.04, 1), (0.04, 2), (0.02, 0), (0.02, 1), (0.02, 2)
    ]
    assert cs[4].design_sets == (
        "simulation.dp=0.02",
        "simulation.perturbation.seed=11",
        "simulation.perturbation.amplitude=1e-06",
    )
    assert len({c.key for c in cs}) == 6


def test_the_observed_order_of_an_analytic_sequence():
    # f = 1 + 2 dp², exact means and no spread: order 2, extrapolated 1
    dp = [0.04, 0.02, 0.01]
    f = [1 + 2 * h * h for h in dp]
    r = observed_order(dp, f, [0.0] * 3, [5] * 3)
    assert r["verdict"] == "converging"
    assert r["order"] == pytest.approx(2.0, rel=1e-9)
    assert r["extrapolated"] == pytest.approx(1.0, rel=1e-9)
    # unequal ratios: f = 3 − dp^1.5 at 0.05, 0.03, 0.01
    dp = [0.05, 0.03, 0.01]
    r = observed_order(dp, [3 - h**1.5 for h in dp], [0.0] * 3, [5] * 3)
    assert r["order"] == pytest.approx(1.5, rel=1e-9)
    assert r["extrapolated"] == pytest.approx(3.0, rel=1e-9)


def test_the_verdicts_when_the_means_do_not_converge():
    dp = [0.04, 0.02, 0.01]
    # the two finest means 0.1 apart, each member's sd 1 over 5 members: se = 0.63
    assert observed_order(dp, [1.5, 1.2, 1.1], [1.0] * 3, [5] * 3)["verdict"] == "within spread"
    assert observed_order(dp, [1.0, 2.0, 1.5], [0.0] * 3, [5] * 3)["verdict"] == "oscillating"
    assert observed_order(dp, [1.0, 1.1, 1.5], [0.0] * 3, [5] * 3)["verdict"] == "diverging"
    assert observed_order(dp[1:], [1.0, 1.5], [0.0] * 2, [5] * 2)["verdict"] == "two levels"
    r = observed_order(dp, [1.0, math.nan, 1.5], [0.0] * 3, [5] * 3)
    assert r["verdict"].startswith("no finished members")
