import pytest

from uma.atomic import atomic_write_text


def test_atomic_write_replaces_whole_file(tmp_path):
    target = tmp_path / "out" / "metrics.json"
    atomic_write_text(target, "first")
    atomic_write_text(target, "second")
    assert target.read_text() == "second"
    assert [p.name for p in target.parent.iterdir()] == ["metrics.json"]


def test_crash_while_writing_keeps_old_file(tmp_path):
    from uma.atomic import atomic_open

    target = tmp_path / "metrics.json"
    atomic_write_text(target, "old")
    with pytest.raises(RuntimeError), atomic_open(target) as handle:
        handle.write("half")
        raise RuntimeError("crash")
    assert target.read_text() == "old"
    assert [p.name for p in tmp_path.iterdir()] == ["metrics.json"]


def test_out_dir_that_is_a_file_is_refused_before_any_work(tmp_path):
    from uma.atomic import prepare_out_dir
    from uma.errors import OutputError

    file = tmp_path / "taken"
    file.write_text("x")
    with pytest.raises(
        OutputError, match="expected a folder for the results, got an existing file"
    ):
        prepare_out_dir(file)
    with pytest.raises(OutputError, match="got an existing file"):
        prepare_out_dir(file / "below")
    assert prepare_out_dir(tmp_path / "new" / "deeper") == tmp_path / "new" / "deeper"
    assert not (tmp_path / "new").exists()


def test_write_failure_is_an_output_error(tmp_path):
    from uma.errors import OutputError

    (tmp_path / "metrics.json").mkdir()  # a folder where the file goes
    with pytest.raises(OutputError, match="metrics.json: cannot write"):
        atomic_write_text(tmp_path / "metrics.json", "x")
    assert [p.name for p in tmp_path.iterdir()] == ["metrics.json"]


# --- whole folders: a results folder is the old run whole or the new run whole -------------

import os  # noqa: E402
import signal  # noqa: E402
import subprocess  # noqa: E402
import sys  # noqa: E402
import textwrap  # noqa: E402
from pathlib import Path  # noqa: E402

OLD = {
    "scenario.yaml": "seed: 1\n",
    "metrics.json": '{"run": "old"}\n',
    "frames.csv": "frame\nold\n",
    "events.csv": "time_ms\nold\n",
}


def _write_run(folder: Path, tag: str) -> None:
    from uma.metrics.results import write_results

    write_results(
        folder,
        scenario_yaml=f"seed: {tag}\n",
        metrics={"run": tag},
        frames_csv=f"frame\n{tag}\n",
        events_csv_text=f"time_ms\n{tag}\n",
    )


def _contents(folder: Path) -> dict[str, str]:
    return {p.name: p.read_text() for p in sorted(folder.iterdir())}


def _runs_in(folder: Path) -> set[str]:
    """Which run each file of the folder comes from ('old' or 'new')."""
    texts = [text for name, text in _contents(folder).items() if name in OLD]
    return {"old" if "old" in text or "1" in text else "new" for text in texts}


@pytest.fixture
def old_run(tmp_path):
    folder = tmp_path / "R"
    folder.mkdir()
    for name, text in OLD.items():
        (folder / name).write_text(text)
    return folder


def test_atomic_dir_replaces_the_folder_whole(old_run):
    _write_run(old_run, "new")
    assert set(_contents(old_run)) == set(OLD)
    assert _runs_in(old_run) == {"new"}
    assert [p.name for p in old_run.parent.iterdir()] == ["R"]  # no hidden sibling left


@pytest.mark.parametrize("step", ["write1", "write2", "write3", "write4", "fsync", "swap"])
def test_write_failure_at_each_step_keeps_the_old_run_whole(old_run, monkeypatch, step):
    import builtins

    import uma.atomic
    import uma.metrics.results
    from uma.errors import OutputError

    def disk_full(*args, **kwargs):
        raise OSError(28, "No space left on device")

    if step.startswith("write"):
        calls = []
        real_open = builtins.open

        def failing_open(*args, **kwargs):
            calls.append(args[0])
            if len(calls) == int(step[-1]):
                disk_full()
            return real_open(*args, **kwargs)

        monkeypatch.setattr(uma.metrics.results, "open", failing_open, raising=False)
    else:
        monkeypatch.setattr(
            uma.atomic, {"fsync": "_fsync_tree", "swap": "_exchange"}[step], disk_full
        )
    with pytest.raises(OutputError, match="R: cannot write .No space left on device"):
        _write_run(old_run, "new")
    assert _contents(old_run) == OLD
    assert [p.name for p in old_run.parent.iterdir()] == ["R"]


def test_without_exchange_the_folder_is_renamed_aside_and_in(old_run, monkeypatch):
    import uma.atomic

    monkeypatch.setattr(uma.atomic, "_exchange", lambda a, b: False)
    _write_run(old_run, "new")
    assert _runs_in(old_run) == {"new"}
    assert [p.name for p in old_run.parent.iterdir()] == ["R"]

    real_rename = os.rename

    def second_rename_fails(src, dst):
        if str(src).endswith(".tmp"):
            raise OSError(5, "Input/output error")
        real_rename(src, dst)

    monkeypatch.setattr(uma.atomic.os, "rename", second_rename_fails)
    before = _contents(old_run)
    with pytest.raises(OSError, match="Input/output error"):
        _write_run(old_run, "newer")
    assert _contents(old_run) == before  # the old folder was put back
    assert [p.name for p in old_run.parent.iterdir()] == ["R"]


_KILLER = """
import os, signal, sys
import uma.atomic, uma.metrics.results
step = sys.argv[2]
def die(*args, **kwargs):
    os.kill(os.getpid(), signal.SIGKILL)
real_open, real_exchange, real_rmtree = open, uma.atomic._exchange, uma.atomic.shutil.rmtree
if step.startswith("write"):
    count = []
    def open_then_die(*args, **kwargs):
        count.append(1)
        if len(count) == int(step[-1]):
            die()
        return real_open(*args, **kwargs)
    uma.metrics.results.open = open_then_die
elif step == "fsync":
    uma.atomic._fsync_tree = die
elif step == "after-swap":
    def swap_then_die(a, b):
        real_exchange(a, b)
        die()
    uma.atomic._exchange = swap_then_die
from uma.metrics.results import write_results
write_results(sys.argv[1], scenario_yaml="seed: new\\n", metrics={"run": "new"},
              frames_csv="frame\\nnew\\n", events_csv_text="time_ms\\nnew\\n")
"""


@pytest.mark.parametrize("step", ["write1", "write3", "write4", "fsync", "after-swap", "none"])
def test_killed_between_steps_leaves_one_run_whole(old_run, step):
    repo = Path(__file__).resolve().parents[1]
    env = dict(os.environ, PYTHONPATH=str(repo))
    done = subprocess.run(
        [sys.executable, "-c", textwrap.dedent(_KILLER), str(old_run), step],
        env=env,
        capture_output=True,
        timeout=30,
    )
    killed = step != "none"
    assert done.returncode == (-signal.SIGKILL if killed else 0), done.stderr
    assert set(_contents(old_run)) == set(OLD)  # no stray .tmp inside the visible folder
    expected = {"new"} if step in ("after-swap", "none") else {"old"}
    assert _runs_in(old_run) == expected
    # The next write clears what the killed writer left beside the folder.
    _write_run(old_run, "new")
    assert [p.name for p in old_run.parent.iterdir()] == ["R"]


def test_a_folder_holding_other_files_is_never_replaced(old_run):
    from uma.atomic import prepare_out_dir
    from uma.errors import OutputError
    from uma.metrics.results import RUN_FILES

    (old_run / "thesis.tex").write_text("mine")
    with pytest.raises(OutputError, match=r"holds files that are not results \(thesis.tex\)"):
        prepare_out_dir(old_run, replaceable=RUN_FILES)
    with pytest.raises(OutputError, match="not results"):
        _write_run(old_run, "new")
    assert (old_run / "thesis.tex").read_text() == "mine"
    assert _runs_in(old_run) == {"old"}


def test_atomic_files_replace_every_file_or_none(tmp_path, monkeypatch):
    import uma.atomic
    from uma.atomic import atomic_files
    from uma.errors import OutputError

    atomic_files(tmp_path, {"a.parquet": b"old", "a.csv": b"old"})
    real_fsync = os.fsync
    calls = []

    def second_fsync_fails(fd):
        calls.append(fd)
        if len(calls) == 2:
            raise OSError(28, "No space left on device")
        real_fsync(fd)

    monkeypatch.setattr(uma.atomic.os, "fsync", second_fsync_fails)
    with pytest.raises(OutputError, match="No space left"):
        atomic_files(tmp_path, {"a.parquet": b"new", "a.csv": b"new"})
    assert {p.name: p.read_bytes() for p in tmp_path.iterdir()} == {
        "a.parquet": b"old",
        "a.csv": b"old",
    }


def test_the_current_folder_is_never_swapped(tmp_path, monkeypatch):
    from uma.errors import OutputError

    monkeypatch.chdir(tmp_path)
    for out in (".", str(tmp_path), ".."):
        with pytest.raises(OutputError, match="other than the current folder"):
            _write_run(Path(out), "new")
    assert list(tmp_path.iterdir()) == []


def test_only_an_ended_writers_leftovers_on_this_host_are_removed(tmp_path):
    import socket

    from uma.atomic import atomic_files

    ended = subprocess.run(
        [sys.executable, "-c", "import os; print(os.getpid())"], capture_output=True
    )
    dead = int(ended.stdout)
    host = socket.gethostname()
    names = {
        f".sweep.csv.uma-{dead}@{host}-abc.tmp": "dead writer here: removed",
        f".sweep.csv.uma-{os.getppid()}@{host}-abc.tmp": "live writer: kept",
        f".sweep.csv.uma-{dead}@elsewhere-abc.tmp": "another host's writer: kept",
        ".sweep.csv.abc.tmp": "not ours: kept",
    }
    for name in names:
        (tmp_path / name).write_text("x")
    atomic_files(tmp_path, {"sweep.csv": b"new"})
    left = {p.name for p in tmp_path.iterdir()}
    assert left == {"sweep.csv"} | {n for n, why in names.items() if why.endswith("kept")}


def test_the_current_folder_is_a_place_for_results(tmp_path, monkeypatch):
    from uma.atomic import prepare_out_dir

    monkeypatch.chdir(tmp_path)
    assert prepare_out_dir(".") == tmp_path.relative_to(tmp_path)  # Path("."), no parts
