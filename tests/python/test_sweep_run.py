"""Running studies: a LocalCluster gives the serial result table, a failing case is a row,
and --resume runs only the missing cases."""

import pathlib

import pandas as pd
import pytest
from conftest import post_coupling
from granmix.cli import main
from granmix.sweep import RUN_COLUMNS

ROOT = pathlib.Path(__file__).resolve().parents[2]

STUDY = f"""\
[study]
name = "small"
scene = "{ROOT}/models/scenes/fmu_barrier_2d.toml"
step = 0.001
end_time = 0.02
{post_coupling(f"{ROOT}/")}
[[parameters]]
name = "friction"
target = "scene:materials.0.friction_angle"
values = [25.0, 35.0]

[[parameters]]
name = "k"
target = "post.k"
values = [2.0e4, 8.0e4]

[[outputs]]
variable = "granmix.barrier.force.x"
reduce = ["max", "mean", "integral", "final"]

[[outputs]]
variable = "post.displacement"
reduce = ["max"]
"""


def study(tmp_path, text=STUDY):
    p = tmp_path / "study.toml"
    p.write_text(text)
    return p


def results(out):
    return pd.read_parquet(out / "results.parquet").drop(columns=list(RUN_COLUMNS))


def run(*args):
    assert main([str(a) for a in args] + ["--quiet"]) == 0


@pytest.fixture(scope="module")
def serial(tmp_path_factory):
    d = tmp_path_factory.mktemp("serial")
    run(study(d), "--out", d / "out", "--serial")
    return d / "out"


def test_a_local_cluster_gives_the_serial_table_bitwise(serial, tmp_path):
    run(study(tmp_path), "--out", tmp_path / "out", "--workers", 2)
    a, b = results(tmp_path / "out"), results(serial)
    assert len(a) == 4 and (a["status"] == "ok").all(), a[["key", "status", "diagnostic"]].to_dict(
        "records"
    )
    pd.testing.assert_frame_equal(a, b, check_exact=True)
    sa = pd.read_parquet(tmp_path / "out" / "series.parquet").sort_values(["key", "time"])
    sb = pd.read_parquet(serial / "series.parquet").sort_values(["key", "time"])
    pd.testing.assert_frame_equal(sa.reset_index(drop=True), sb.reset_index(drop=True))
    # the reductions are those of the time series
    s = sb[sb["key"] == a["key"][0]]
    f = s["granmix.barrier.force.x"].to_numpy()
    assert a["granmix.barrier.force.x:max"][0] == f.max()
    assert a["granmix.barrier.force.x:final"][0] == f[-1]
    trapz = float(((f[1:] + f[:-1]) * 0.5 * 0.001).sum())
    assert abs(a["granmix.barrier.force.x:integral"][0] - trapz) <= 1e-12 * abs(trapz)
    assert abs(a["granmix.barrier.force.x:mean"][0] - trapz / 0.02) <= 1e-12 * abs(trapz)
    # the friction angle reaches the packed scene: a steeper soil pushes less
    assert a["granmix.barrier.force.x:max"][2] < a["granmix.barrier.force.x:max"][0]


def test_a_blown_up_case_is_a_failed_row_and_the_study_goes_on(tmp_path):
    text = STUDY.replace("values = [25.0, 35.0]", "values = [25.0]") + (
        '\n[[parameters]]\nname = "max_speed"\ntarget = "scene:simulation.max_speed"\n'
        "values = [50.0, 0.002]\n"
    )
    run(study(tmp_path, text), "--out", tmp_path / "out", "--serial")
    r = results(tmp_path / "out")
    assert list(r["status"]) == ["ok", "failed", "ok", "failed"]
    bad = r[r["status"] == "failed"]["diagnostic"]
    # 0.002 m/s passes the scene check (one step of gravity, 1.04e-3 m/s, stays below
    # it; 0.001 is refused when the FMU is packed), then the stability guard stops the
    # soil, or the post's motion of the barrier is refused, whichever passes the bound
    # first; either way the FMU's own message names the bound
    assert bad.str.contains("numerical blow-up|beyond simulation.max_speed").all(), list(bad)
    assert bad.str.contains("simulation.max_speed").all(), list(bad)


def test_resume_runs_only_the_missing_cases(tmp_path, capsys):
    out = tmp_path / "out"
    run(study(tmp_path), "--out", out, "--serial")
    full = results(out)
    # an interrupted study: cases 1 and 3 never stored
    for key in full["key"].iloc[[1, 3]]:
        (out / "cases" / f"{key}.parquet").unlink()
    capsys.readouterr()
    run(study(tmp_path), "--out", out, "--serial", "--resume")
    assert "4 cases (2 run now)" in capsys.readouterr().out
    pd.testing.assert_frame_equal(results(out), full, check_exact=True)


def test_a_bad_study_file_is_one_clear_error(tmp_path, capsys):
    code = main([str(study(tmp_path, STUDY.replace("step = 0.001", "stepp = 0.001")))])
    assert code == 2
    err = capsys.readouterr().err
    assert "study.toml:4: `study.stepp`: unknown key" in err, err


@pytest.mark.parametrize(
    ("change", "key", "says"),
    [
        (('to = "post.force"', 'to = "post.forse"'), "connections[0].to", "no variable `forse`"),
        (('from = "post.displacement"', 'from = "post.force"'), "connections[1].from", "input"),
        (('target = "post.k"', 'target = "post.stiffness"'), "parameters[1].target", "stiffness"),
        (
            ("scene:materials.0.friction_angle", "scene:materials.0.frictionn_angle"),
            "parameters[0].target",
            "granmix refuses it",
        ),
    ],
)
def test_a_study_is_held_against_its_fmus_before_any_case_runs(tmp_path, capsys, change, key, says):
    text = STUDY.replace(*change)
    code = main([str(study(tmp_path, text)), "--out", str(tmp_path / "out"), "--quiet"])
    err = capsys.readouterr().err
    assert code == 2, err
    line = next(i + 1 for i, s in enumerate(text.splitlines()) if change[1] in s)
    assert f"study.toml:{line}: `{key}`" in err, err
    assert says in err, err
    assert not (tmp_path / "out" / "results.parquet").exists()


def test_a_worker_killed_mid_case_loses_no_row(tmp_path):
    """A worker process is killed while it runs a case: Dask runs that case again on
    another worker, and the study returns every row exactly once, each equal to the
    serial result."""
    import os
    import signal
    import threading
    import time

    from distributed import Client, LocalCluster
    from granmix import cases, load_study
    from granmix.sweep import run_dask, run_serial, table

    s = load_study(study(tmp_path, STUDY.replace("end_time = 0.02", "end_time = 1.0")))
    todo = cases(s)
    fmus = tmp_path / "fmus"
    serial = table(run_serial(s, todo, fmus)).drop(columns=list(RUN_COLUMNS))
    with (
        LocalCluster(
            n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None
        ) as cluster,
        Client(cluster) as client,
    ):
        box = {}
        runner = threading.Thread(target=lambda: box.update(r=run_dask(s, todo, fmus, client)))
        runner.start()
        busy = {}
        deadline = time.monotonic() + 60
        while not busy and time.monotonic() < deadline:
            busy = {w: tasks for w, tasks in client.processing().items() if tasks}
            time.sleep(0.02)
        assert busy, "no case started"
        victim = next(iter(busy))
        pid = client.run(os.getpid, workers=[victim])[victim]
        os.kill(pid, signal.SIGKILL)
        runner.join(timeout=300)
        assert "r" in box, "the study did not finish"
    rows = table(box["r"]).drop(columns=list(RUN_COLUMNS))
    assert rows["key"].is_unique and len(rows) == len(todo)
    pd.testing.assert_frame_equal(rows, serial, check_exact=True)
