"""Studies lose no work: an interrupted study keeps every finished case and `--resume`
runs only the rest; a resume after the study file changed keeps no stale row; a design
with a repeated case gives every case a row; a study on an external scheduler survives
its client being killed, and its client survives the scheduler's death."""

import os
import pathlib
import re
import shutil
import signal
import socket
import subprocess
import sys
import threading
import time

import pandas as pd
import pytest
from conftest import post_coupling
from granmix.cli import main
from granmix.sweep import RUN_COLUMNS

ROOT = pathlib.Path(__file__).resolve().parents[2]
VENV_BIN = pathlib.Path(sys.executable).parent

# 4 cases of about 0.4 s each (400 communication steps): long enough to stop a study
# between two cases, short enough for a test
STUDY = f"""\
[study]
name = "resumable"
scene = "{ROOT}/models/scenes/fmu_barrier_2d.toml"
step = 0.001
end_time = 0.4
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
reduce = ["max", "mean"]

[[outputs]]
variable = "post.displacement"
reduce = ["max"]
"""


def write_study(directory: pathlib.Path, text: str = STUDY) -> pathlib.Path:
    p = directory / "study.toml"
    p.write_text(text)
    return p


def results(out: pathlib.Path) -> pd.DataFrame:
    return pd.read_parquet(out / "results.parquet").drop(columns=list(RUN_COLUMNS))


def series(out: pathlib.Path) -> pd.DataFrame:
    s = pd.read_parquet(out / "series.parquet")
    return s.sort_values(["key", "time"]).reset_index(drop=True)


def run(*args) -> None:
    assert main([str(a) for a in args] + ["--quiet"]) == 0


@pytest.fixture(scope="module")
def clean(tmp_path_factory) -> pathlib.Path:
    """The study run once from start to end, serially."""
    d = tmp_path_factory.mktemp("clean")
    run(write_study(d), "--out", d / "out", "--serial")
    return d / "out"


class Cli:
    """`granmix-sweep` in a child process, its progress read from stderr as it goes."""

    def __init__(self, *args) -> None:
        cmd = [str(VENV_BIN / "granmix-sweep"), *map(str, args)]
        # Ctrl-C raises KeyboardInterrupt in the child, as at a terminal: a test run
        # started in the background by a non-interactive shell has SIGINT ignored,
        # which a child inherits (and Python then keeps ignoring it), while a handled
        # signal is reset to its default action by exec
        old = signal.signal(signal.SIGINT, signal.default_int_handler)
        try:
            self.proc = subprocess.Popen(
                cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE
            )
        finally:
            signal.signal(signal.SIGINT, old)
        self.err = b""
        self.reader = threading.Thread(target=self._read, daemon=True)
        self.reader.start()

    def _read(self) -> None:
        assert self.proc.stderr is not None
        while chunk := self.proc.stderr.read1(4096):
            self.err += chunk

    def done(self, total: int) -> int:
        """Cases the progress display has counted done so far."""
        found = re.findall(rf"(\d+)/{total}\b", self.err.decode(errors="replace"))
        return max(map(int, found), default=0)

    def wait_done(self, n: int, total: int, timeout: float = 60.0) -> None:
        deadline = time.monotonic() + timeout
        while self.done(total) < n:
            assert self.proc.poll() is None, (
                f"the study ended early: {self.err.decode()}"
            )
            assert time.monotonic() < deadline, f"no progress: {self.err.decode()}"
            time.sleep(0.01)

    def finish(self, timeout: float = 60.0) -> int:
        code = self.proc.wait(timeout)
        self.reader.join(timeout)
        return code


def stored(out: pathlib.Path) -> int:
    """Cases whose row is on disk (the study's store, `<out>/cases/<key>.parquet`)."""
    d = out / "cases"
    if not d.is_dir():
        return 0
    return sum(1 for p in d.glob("*.parquet") if not p.name.endswith(".series.parquet"))


@pytest.mark.parametrize(
    "stop", [signal.SIGINT, signal.SIGTERM], ids=["SIGINT", "SIGTERM"]
)
def test_an_interrupted_study_resumes_with_only_the_missing_cases(
    clean, tmp_path, capsys, stop
):
    """Ctrl-C (or a batch system's SIGTERM) after two of four cases: the two finished
    cases are on disk, `--resume` runs only the other two, and the table and the series
    equal a clean run's."""
    out = tmp_path / "out"
    study = write_study(tmp_path)
    cli = Cli(study, "--out", out, "--serial")
    cli.wait_done(2, 4)
    cli.proc.send_signal(stop)
    code = cli.finish()
    finished = cli.done(4)
    assert 2 <= finished < 4, "the study ended before the interrupt"
    capsys.readouterr()
    run(study, "--out", out, "--serial", "--resume")
    said = capsys.readouterr().out
    assert f"4 cases ({4 - finished} run now)" in said, said
    pd.testing.assert_frame_equal(results(out), results(clean), check_exact=True)
    pd.testing.assert_frame_equal(series(out), series(clean), check_exact=True)
    # the study stops with the shell's code for Ctrl-C, and says how to go on
    err = cli.err.decode()
    assert code == 128 + signal.SIGINT, err
    assert "--resume" in err and f"{finished} of 4 cases stored" in err, err


def test_resume_after_an_edited_end_time_keeps_no_stale_row(clean, tmp_path, capsys):
    """The end time edited after a full run: every case runs again under its new key,
    and the table holds the four new rows only, once each."""
    out = tmp_path / "out"
    shutil.copytree(clean, out)
    study = write_study(tmp_path, STUDY.replace("end_time = 0.4", "end_time = 0.05"))
    capsys.readouterr()
    run(study, "--out", out, "--serial", "--resume")
    assert "4 cases (4 run now)" in capsys.readouterr().out
    r = results(out)
    assert list(r["case"]) == [0, 1, 2, 3], r[["key", "case"]]
    from granmix import cases, load_study

    assert list(r["key"]) == [c.key for c in cases(load_study(study))]
    s = series(out)
    assert set(s["key"]) == set(r["key"])
    assert (s.groupby("key")["time"].max() == 0.05).all()


def test_a_design_with_a_repeated_case_gives_every_case_a_row(tmp_path, capsys):
    """An explicit list that holds the same case twice, on a 2-worker LocalCluster: three
    cases, three rows, the repeat equal to the first (a case depends only on its
    values). The local cluster's dashboard link is printed."""
    text = (
        STUDY.replace("end_time = 0.4", "end_time = 0.02")
        .replace("values = [25.0, 35.0]\n", "")
        .replace("values = [2.0e4, 8.0e4]\n", "")
        + '\n[design]\nkind = "list"\ncases = [{friction = 25.0, k = 2.0e4},'
        " {friction = 35.0, k = 8.0e4}, {friction = 25.0, k = 2.0e4}]\n"
    )
    out = tmp_path / "out"
    run(write_study(tmp_path, text), "--out", out, "--workers", 2)
    r = results(out)
    assert list(r["case"]) == [0, 1, 2], r[["key", "case"]]
    assert r["key"].is_unique
    assert (r["status"] == "ok").all()
    same = [c for c in r.columns if c not in ("key", "case")]
    pd.testing.assert_series_equal(r.loc[0, same], r.loc[2, same], check_names=False)
    assert re.search(r"dashboard: http://\S+/status", capsys.readouterr().err)


class Cluster:
    """A Dask scheduler and worker in processes of their own."""

    def __init__(
        self, address: str, scheduler: subprocess.Popen, worker: subprocess.Popen
    ) -> None:
        self.address, self.scheduler, self.worker = address, scheduler, worker

    def wait_idle(self, timeout: float = 60.0) -> None:
        """Until the worker runs no task, cancelled ones included (a task whose client
        has gone runs to its end)."""
        from distributed import Client

        def running(dask_worker) -> int:
            return dask_worker.state.executing_count

        deadline = time.monotonic() + timeout
        with Client(self.address, timeout=30) as client:
            while any(client.run(running).values()):
                assert time.monotonic() < deadline, "the worker is still busy"
                time.sleep(0.05)


@pytest.fixture
def external_cluster(tmp_path):
    """`dask scheduler` and `dask worker` (one worker process named `w0`, without a
    nanny, so that a case waits while another runs) started as processes of their
    own."""
    info = tmp_path / "scheduler.json"
    procs = [
        subprocess.Popen(
            [str(VENV_BIN / "dask"), "scheduler", "--host", "127.0.0.1", "--port", "0"]
            + ["--no-dashboard", "--scheduler-file", str(info)],
            stdout=subprocess.DEVNULL,
            stderr=subprocess.DEVNULL,
        )
    ]
    try:
        deadline = time.monotonic() + 60
        while not info.is_file() and time.monotonic() < deadline:
            time.sleep(0.05)
        procs.append(
            subprocess.Popen(
                [str(VENV_BIN / "dask"), "worker", "--scheduler-file", str(info)]
                + ["--no-nanny", "--nthreads", "1", "--name", "w0", "--no-dashboard"],
                stdout=subprocess.DEVNULL,
                stderr=subprocess.DEVNULL,
            )
        )
        from distributed import Client

        with Client(scheduler_file=str(info), timeout=60) as client:
            client.wait_for_workers(1, timeout=60)
            address = client.scheduler.address
        yield Cluster(address, procs[0], procs[1])
    finally:
        # the worker first: it closes at once when its scheduler is still there
        for p in reversed(procs):
            if p.poll() is None:
                p.send_signal(signal.SIGINT)
            try:
                p.wait(30)
            except subprocess.TimeoutExpired:
                p.kill()
                p.wait()


def test_a_study_on_an_external_scheduler_survives_a_killed_client(
    clean, tmp_path, capsys, external_cluster
):
    """A study on a scheduler and a worker started apart from it. Its client is killed
    (SIGKILL) after two cases: those are on disk, and so is the case the worker was
    running then. `--resume` on the same scheduler runs only the rest; the table equals
    the serial one, and `host` names the worker of each case."""
    out = tmp_path / "out"
    study = write_study(tmp_path)
    cli = Cli(study, "--out", out, "--scheduler", external_cluster.address)
    cli.wait_done(2, 4)
    cli.proc.kill()
    cli.finish()
    finished = cli.done(4)
    # the worker finishes the case it was running when the client died
    external_cluster.wait_idle()
    kept = stored(out)
    assert kept >= finished, (
        f"the killed client's study kept {kept} of the {finished} cases it had finished"
    )
    assert kept < 4, "the study ended before the client was killed"
    capsys.readouterr()
    run(study, "--out", out, "--scheduler", external_cluster.address, "--resume")
    said = capsys.readouterr().out
    assert f"4 cases ({4 - kept} run now)" in said, said
    pd.testing.assert_frame_equal(results(out), results(clean), check_exact=True)
    pd.testing.assert_frame_equal(series(out), series(clean), check_exact=True)
    hosts = set(pd.read_parquet(out / "results.parquet")["host"])
    assert hosts == {f"{socket.gethostname()}/w0"}, hosts


def test_a_study_that_loses_its_scheduler_stops_and_resumes(
    clean, tmp_path, capsys, external_cluster
):
    """The scheduler is killed after two cases: the client stops with an error that
    says how to go on, the finished cases are on disk, and `--resume` (here serially)
    runs only the rest; the table equals a clean run's."""
    out = tmp_path / "out"
    study = write_study(tmp_path)
    cli = Cli(study, "--out", out, "--scheduler", external_cluster.address)
    cli.wait_done(2, 4)
    external_cluster.scheduler.kill()
    code = cli.finish()
    finished = cli.done(4)
    # the worker, alone, is stopped too: nothing more can arrive
    external_cluster.worker.kill()
    external_cluster.worker.wait()
    kept = stored(out)
    assert kept >= finished, (
        f"the study that lost its scheduler kept {kept} of the {finished} cases it had finished"
    )
    err = cli.err.decode()
    assert code == 1, err
    assert "lost the cluster" in err and "--resume" in err, err
    capsys.readouterr()
    run(study, "--out", out, "--serial", "--resume")
    said = capsys.readouterr().out
    assert f"4 cases ({4 - kept} run now)" in said, said
    pd.testing.assert_frame_equal(results(out), results(clean), check_exact=True)


def test_a_resume_after_a_full_run_runs_nothing(clean, tmp_path, capsys):
    out = tmp_path / "out"
    shutil.copytree(clean, out)
    capsys.readouterr()
    run(write_study(tmp_path), "--out", out, "--serial", "--resume")
    assert "4 cases (0 run now)" in capsys.readouterr().out
    pd.testing.assert_frame_equal(results(out), results(clean), check_exact=True)
    pd.testing.assert_frame_equal(series(out), series(clean), check_exact=True)


def test_a_resume_keeps_the_rows_of_a_table_written_before_the_store(
    clean, tmp_path, capsys
):
    """An output directory with only `results.parquet` and `series.parquet` (a study run
    before cases were stored one by one): `--resume` stores their rows and runs nothing."""
    out = tmp_path / "out"
    shutil.copytree(clean, out)
    shutil.rmtree(out / "cases")
    capsys.readouterr()
    run(write_study(tmp_path), "--out", out, "--serial", "--resume")
    assert "4 cases (0 run now)" in capsys.readouterr().out
    pd.testing.assert_frame_equal(results(out), results(clean), check_exact=True)
    pd.testing.assert_frame_equal(series(out), series(clean), check_exact=True)


# --- issue 74: resume as a clean run, extracted FMUs, new reductions -----------------

def test_a_new_reduction_is_computed_from_the_stored_series(clean, tmp_path, capsys):
    """`min` added to an output the study already collects: the resume runs nothing,
    says every case is stored, and the new column is each case's stored series reduced
    (a reference computed here with pandas); the other columns are the clean run's."""
    out = tmp_path / "out"
    shutil.copytree(clean, out)
    study = write_study(tmp_path, STUDY.replace('reduce = ["max", "mean"]',
                                                'reduce = ["max", "mean", "min"]'))
    capsys.readouterr()
    run(study, "--out", out, "--serial", "--resume")
    captured = capsys.readouterr()
    assert "4 cases (0 run now)" in captured.out, captured.out
    assert "resume: 4 of 4 cases stored, 0 to run" in captured.err, captured.err
    r = results(out)
    col = "granmix.barrier.force.x:min"
    expected = series(clean).groupby("key")["granmix.barrier.force.x"].min()
    assert list(r[col]) == [expected[k] for k in r["key"]]
    pd.testing.assert_frame_equal(r.drop(columns=[col]), results(clean), check_exact=True)


def test_a_resume_whose_first_pending_case_is_refused_makes_it_a_failed_row(
    tmp_path, capsys
):
    """The second case's friction angle (95°) is one granmix refuses to pack: a clean run
    makes it a failed row. With only the first case stored, `--resume` (and
    `--resume --retry-failed`) did the preflight on that case and refused the whole
    study (exit 2); it now runs it as the clean run does."""
    text = STUDY.replace("values = [25.0, 35.0]", "values = [25.0, 95.0]").replace(
        "values = [2.0e4, 8.0e4]", "values = [2.0e4]").replace("end_time = 0.4",
                                                               "end_time = 0.02")
    study = write_study(tmp_path, text)
    clean_out, out = tmp_path / "clean", tmp_path / "out"
    run(study, "--out", clean_out, "--serial")
    r = results(clean_out)
    assert list(r["status"]) == ["ok", "failed"], r
    assert "friction_angle" in r["diagnostic"].iloc[1], r["diagnostic"].iloc[1]
    shutil.copytree(clean_out, out)
    (out / "cases" / f"{r['key'].iloc[1]}.parquet").unlink()
    for extra in ([], ["--retry-failed"]):
        capsys.readouterr()
        run(study, "--out", out, "--serial", "--resume", *extra)
        assert "2 cases (1 run now)" in capsys.readouterr().out
        pd.testing.assert_frame_equal(results(out).drop(columns=["diagnostic"]),
                                      r.drop(columns=["diagnostic"]), check_exact=True)


def test_fmus_left_extracted_by_dead_processes_are_cleared(clean, tmp_path, capsys):
    """A process killed mid-case leaves its extracted FMUs (about 9 MB each) under the
    pack cache's `extracted/`; the next study clears those of this host's processes that
    are gone, keeps those of live ones, and a study's own cases leave nothing there."""
    from granmix import extracted

    out = tmp_path / "out"
    shutil.copytree(clean, out)
    root = extracted.root(out / "fmus")
    assert not root.exists() or not any(root.iterdir()), "a clean run left FMUs extracted"
    dead = subprocess.Popen([sys.executable, "-c", "pass"])
    dead.wait()
    host = socket.gethostname().replace("-", "_")
    stale = root / f"{host}-{dead.pid}-abc"
    live = root / f"{host}-{os.getpid()}-def"
    other = root / f"elsewhere-{dead.pid}-ghi"
    for d in (stale, live, other):
        d.mkdir(parents=True)
        (d / "binaries.so").write_bytes(b"x" * 1000)
    capsys.readouterr()
    run(write_study(tmp_path), "--out", out, "--serial", "--resume")
    assert "cleared 1 extracted FMU folder(s)" in capsys.readouterr().err
    assert not stale.exists() and live.exists() and other.exists()
