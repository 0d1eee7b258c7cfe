"""Studies turn every failure into a row or a clear study error: a start value a
partner FMU refuses (its own message, nothing left behind), a typo in `study.set`, a
worker that keeps dying, a case over the wall-time limit. Plots carry units, a title
and one curve per value of the other parameters; `--variables` lists the FMUs'
variable names."""

import os
import pathlib
import signal
import subprocess
import sys
import tempfile
import threading
import time

import pandas as pd
import pytest
from conftest import post_coupling
from granmix.cli import main

ROOT = pathlib.Path(__file__).resolve().parents[2]

STUDY = f"""\
[study]
name = "failing"
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
reduce = ["max", "integral"]
"""


def write_study(directory: pathlib.Path, text: str = STUDY) -> pathlib.Path:
    p = directory / "study.toml"
    p.write_text(text)
    return p


def run(*args) -> None:
    assert main([str(a) for a in args] + ["--quiet"]) == 0


def fmu_message(fmu: pathlib.Path, start: dict) -> str:
    """What the FMU itself logs when it is started with ``start`` (fmpy's own loop)."""
    from fmpy import simulate_fmu

    logged = []

    def logger(_component, _instance, _status, _category, message):
        logged.append(message.decode())

    with pytest.raises(Exception):  # noqa: B017 - fmpy raises a bare Exception
        simulate_fmu(str(fmu), start_values=start, stop_time=0.001, logger=logger)
    assert logged, "the FMU logged nothing"
    return logged[-1]


def test_a_refused_partner_start_value_is_a_failed_row_with_the_fmus_message(
    tmp_path, monkeypatch
):
    """`post.k = -1e9`: the post refuses it at start. The case is a failed row carrying
    the post's own message; its instances are freed and their extracted directories
    removed (the temporary directory is empty afterwards); the next case runs."""
    text = STUDY.replace("values = [25.0, 35.0]", "values = [25.0]").replace(
        "values = [2.0e4, 8.0e4]", "values = [-1.0e9, 2.0e4]"
    )
    scratch = tmp_path / "tmp"
    scratch.mkdir()
    monkeypatch.setattr(tempfile, "tempdir", str(scratch))
    out = tmp_path / "out"
    run(write_study(tmp_path, text), "--out", out, "--serial")
    left = os.listdir(scratch)
    r = pd.read_parquet(out / "results.parquet")
    assert list(r["status"]) == ["failed", "ok"], r[["status", "diagnostic"]]
    monkeypatch.undo()
    (post,) = (out / "fmus").glob("post-*.fmu")
    said = fmu_message(post, {"k": -1.0e9})
    diagnostic = r["diagnostic"][0]
    assert said in diagnostic and not left, (
        f"diagnostic: {diagnostic!r}; the FMU said: {said!r}; left in the temporary "
        f"directory: {left}"
    )
    assert diagnostic.startswith("post: "), diagnostic


def test_a_typo_in_study_set_is_reported_against_study_set_and_its_line(
    tmp_path, capsys
):
    """`study.set` names a key the scene does not have, in a study that also varies a
    scene key of the same table: the error names `study.set` and the line of the bad
    override, not the parameter."""
    text = STUDY.replace(
        "end_time = 0.02\n",
        'end_time = 0.02\nset = [\n    "simulation.dp=0.01",\n'
        '    "materials.0.frictionn_angle=30.0",\n]\n',
    )
    code = main(
        [str(write_study(tmp_path, text)), "--out", str(tmp_path / "out"), "--quiet"]
    )
    err = capsys.readouterr().err
    assert code == 2, err
    line = next(
        i + 1 for i, s in enumerate(text.splitlines()) if "frictionn_angle" in s
    )
    assert f"study.toml:{line}: `study.set`" in err, err
    assert "frictionn_angle" in err, err
    assert not (tmp_path / "out" / "results.parquet").exists()


def test_a_case_whose_worker_keeps_dying_is_a_failed_row(tmp_path):
    """With no retries allowed (distributed.scheduler.allowed-failures = 0), the worker
    running a case is killed: the case becomes a failed row naming KilledWorker, and
    the study returns the other case, run on the other worker."""
    import dask
    from distributed import Client, LocalCluster
    from granmix import cases, load_study
    from granmix.sweep import run_dask

    text = STUDY.replace("end_time = 0.02", "end_time = 2.0").replace(
        "values = [25.0, 35.0]", "values = [25.0]"
    )
    s = load_study(write_study(tmp_path, text))
    todo = cases(s)
    with (
        dask.config.set({"distributed.scheduler.allowed-failures": 0}),
        LocalCluster(
            n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None
        ) as cluster,
        Client(cluster) as client,
    ):
        box: dict = {}

        def study() -> None:
            try:
                box["rows"] = run_dask(s, todo, tmp_path / "fmus", client)
            except BaseException as e:  # noqa: BLE001 - the test reports it
                box["error"] = e

        runner = threading.Thread(target=study)
        runner.start()
        # one case on each worker (a dying worker takes down every task it holds)
        busy: dict = {}
        deadline = time.monotonic() + 60
        while len(busy) < 2 and time.monotonic() < deadline:
            busy = {w: t for w, t in client.processing().items() if t}
            time.sleep(0.02)
        assert len(busy) == 2, f"the cases did not start: {busy}"
        worker, (victim,) = min(busy.items())
        # the case is in its master loop, not still packing its FMUs
        time.sleep(0.5)
        pid = client.run(os.getpid, workers=[worker])[worker]
        os.kill(pid, signal.SIGKILL)
        runner.join(timeout=120)
    assert "error" not in box, f"the study was lost: {box['error']!r}"
    rows = {r.key: r for r in box["rows"]}
    assert len(rows) == 2
    dead = rows[victim.removeprefix("case-")]
    assert dead.status == "failed"
    assert "KilledWorker" in dead.diagnostic and "died" in dead.diagnostic, (
        dead.diagnostic
    )
    (other,) = (r for k, r in rows.items() if r is not dead)
    assert other.status == "ok", other.diagnostic


def test_a_case_over_the_wall_time_limit_is_a_failed_row(tmp_path):
    """`study.wall_time_limit` stops a case that runs longer as a failed row with the
    reason; `--wall-time-limit` sets it from the command line."""
    text = STUDY.replace(
        "end_time = 0.02", "end_time = 5.0\nwall_time_limit = 0.2"
    ).replace("values = [25.0, 35.0]", "values = [25.0]")
    out = tmp_path / "out"
    started = time.perf_counter()
    run(write_study(tmp_path, text), "--out", out, "--serial")
    took = time.perf_counter() - started
    r = pd.read_parquet(out / "results.parquet")
    assert list(r["status"]) == ["failed", "failed"], r[["status", "diagnostic"]]
    assert r["diagnostic"].str.contains("wall-time limit of 0.2 s reached").all(), list(
        r["diagnostic"]
    )
    assert (r["wall_time"] < 2.0).all(), list(r["wall_time"])
    assert took < 15, took
    # the same from the command line, for a study without a limit
    run(
        write_study(tmp_path, text.replace("wall_time_limit = 0.2", "")),
        "--out",
        out,
        "--serial",
        "--wall-time-limit",
        0.3,
    )
    r = pd.read_parquet(out / "results.parquet")
    assert r["diagnostic"].str.contains("wall-time limit of 0.3 s reached").all()


def test_resume_keeps_failed_rows_and_retry_failed_runs_them_again(tmp_path, capsys):
    """Cases stopped by the wall-time limit: `--resume` keeps their failed rows,
    `--resume --retry-failed` without the limit runs them again to the end."""
    # 500 steps of about 1 ms each: 5 times the limit
    text = STUDY.replace("end_time = 0.02", "end_time = 0.5").replace(
        "values = [25.0, 35.0]", "values = [25.0]"
    )
    out = tmp_path / "out"
    study = write_study(tmp_path, text)
    run(study, "--out", out, "--serial", "--wall-time-limit", 0.1)
    assert (pd.read_parquet(out / "results.parquet")["status"] == "failed").all()
    capsys.readouterr()
    run(study, "--out", out, "--serial", "--resume")
    assert "2 cases (0 run now), 2 failed" in capsys.readouterr().out
    run(study, "--out", out, "--serial", "--resume", "--retry-failed")
    assert "2 cases (2 run now), 0 failed" in capsys.readouterr().out
    r = pd.read_parquet(out / "results.parquet")
    assert (r["status"] == "ok").all() and list(r["case"]) == [0, 1]


def test_plots_carry_units_a_title_and_one_curve_per_value_of_the_other_parameter(
    tmp_path,
):
    """A 2 × 2 grid: the plot against the friction angle has one line per post
    stiffness (and the other way round), units on both axes (the study's for the scene
    key, the FMUs' for the rest; an integral's times s) and a title."""
    from granmix import load_study
    from granmix.cli import figures

    text = STUDY.replace(
        "values = [25.0, 35.0]\n", 'values = [25.0, 35.0]\nunit = "deg"\n'
    )
    s = load_study(write_study(tmp_path, text))
    rows = pd.DataFrame(
        {
            "friction": [25.0, 25.0, 35.0, 35.0],
            "k": [2.0e4, 8.0e4, 2.0e4, 8.0e4],
            "granmix.barrier.force.x:max": [4.0, 3.0, 2.0, 1.0],
            "granmix.barrier.force.x:integral": [0.4, 0.3, 0.2, 0.1],
            "status": ["ok"] * 4,
        }
    )
    units = {"friction": "deg", "k": "N/m", "granmix.barrier.force.x": "N/m"}
    figs = dict(figures(s, rows, units))
    assert len(figs) == 4, list(figs)
    ax = figs["granmix.barrier.force.x_max__friction"].axes[0]
    assert ax.get_xlabel() == "friction [deg]"
    assert ax.get_ylabel() == "max of granmix.barrier.force.x [N/m]"
    assert ax.get_title() == "failing: max of granmix.barrier.force.x against friction"
    lines = {line.get_label(): list(line.get_ydata()) for line in ax.get_lines()}
    assert lines == {"k = 20000 N/m": [4.0, 2.0], "k = 80000 N/m": [3.0, 1.0]}
    ax = figs["granmix.barrier.force.x_integral__k"].axes[0]
    assert ax.get_ylabel() == "integral of granmix.barrier.force.x [N·s/m]"
    assert {line.get_label() for line in ax.get_lines()} == {
        "friction = 25 deg",
        "friction = 35 deg",
    }
    # a Latin hypercube: twelve values of the other parameter are a colour scale
    n = 12
    lhs = pd.DataFrame(
        {
            "friction": [20.0 + i for i in range(n)],
            "k": [1.0e4 * (1 + (7 * i) % n) for i in range(n)],
            "granmix.barrier.force.x:max": [float(i) for i in range(n)],
            "granmix.barrier.force.x:integral": [0.1 * i for i in range(n)],
            "status": ["ok"] * n,
        }
    )
    fig = dict(figures(s, lhs, units))["granmix.barrier.force.x_max__friction"]
    ax, bar = fig.axes
    assert not ax.get_lines() and len(ax.collections) == 1
    assert bar.get_ylabel() == "k [N/m]"
    import matplotlib.pyplot as plt

    plt.close("all")


def test_variables_lists_the_fmus_variable_names_and_units(tmp_path, capsys):
    code = main(
        [str(write_study(tmp_path)), "--out", str(tmp_path / "out"), "--variables"]
    )
    said = capsys.readouterr().out
    assert code == 0, said
    lines = said.splitlines()

    def line_of(name: str) -> list[str]:
        return next(ln.split() for ln in lines if f" {name} " in ln)

    assert line_of("granmix.barrier.force.x")[:3] == [
        "output",
        "granmix.barrier.force.x",
        "N/m",
    ]
    assert line_of("granmix.barrier.displacement.x")[0] == "input"
    assert line_of("post.k")[:3] == ["parameter", "post.k", "N/m"]
    assert line_of("post.force")[0] == "input"
    assert not (tmp_path / "out" / "results.parquet").exists()


AFTER_A_STUDY = """
import sys
from fmpy import extract, read_model_description
from fmpy.fmi2 import FMU2Slave
from granmix.cli import main

assert main([sys.argv[1], "--out", sys.argv[2], "--serial", "--quiet"]) == 0
# fmpy's own instance, with fmpy's own logger, after the study's instances are gone
md = read_model_description(sys.argv[3])
fmu = FMU2Slave(guid=md.guid, unzipDirectory=extract(sys.argv[3]),
                modelIdentifier=md.coSimulation.modelIdentifier, instanceName="after")
fmu.instantiate()
fmu.setupExperiment(startTime=0.0)
fmu.enterInitializationMode()
fmu.exitInitializationMode()
vr = {v.name: v.valueReference for v in md.modelVariables}
fmu.setReal([vr["barrier.displacement.x"]], [-0.09])
try:
    fmu.doStep(currentCommunicationPoint=0.0, communicationStepSize=1e-3)
except Exception:
    print("refused")
"""


def test_fmpy_logs_after_a_serial_study_without_crashing(tmp_path, fmus):
    """A serial study's instances each registered their own logger with fmpy's native
    proxy, whose one process-wide pointer then dangled: the next FMU fmpy ran in the
    same process crashed (SIGSEGV) on its first log message."""
    text = STUDY.replace("values = [25.0, 35.0]", "values = [25.0, 28.0, 31.0, 35.0]")
    study = tmp_path / "study.toml"
    study.write_text(text)
    script = tmp_path / "after.py"
    script.write_text(AFTER_A_STUDY)
    r = subprocess.run(
        [sys.executable, str(script), str(study), str(tmp_path / "out"), str(fmus["barrier"])],
        capture_output=True,
        text=True,
        timeout=300,
        check=False,
    )
    assert r.returncode == 0, (r.returncode, r.stdout[-2000:], r.stderr[-2000:])
    # the blow-up's message reaches fmpy's printer, then the step is refused
    assert "numerical blow-up" in r.stdout and "refused" in r.stdout, r.stdout[-2000:]
