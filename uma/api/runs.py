"""`uma.run` and `uma.read_run`: one run as a Python object, byte for byte what `uma run` writes.

A `Run` holds the bytes of the four result files (`scenario.yaml`, `metrics.json`, `frames.csv`,
`events.csv`) as `uma.sim.summary.save_run` writes them; `.metrics`, `.frames` and `.events` are
parsed from those bytes, and `.save()` writes those bytes, so the Python view and the files can
never disagree. Column units are in the names (see docs/api.md).
"""

from __future__ import annotations

import json
import os
from collections.abc import Mapping
from functools import cached_property
from pathlib import Path
from typing import TYPE_CHECKING, Any

from uma.errors import ConfigError

if TYPE_CHECKING:
    import pandas as pd
    from matplotlib.figure import Figure

    from uma.config.scenario import Scenario

__all__ = ["Run", "run", "read_run", "folder_path", "RESULT_FILES"]

RESULT_FILES = ("scenario.yaml", "metrics.json", "frames.csv", "events.csv")
# frames.csv takes about 200 bytes a frame: 512 MiB is some 30 hours at 25 frames/s.
MAX_FILE_BYTES = 512 * 1024 * 1024


def folder_path(value: Any, what: str, expected: str = "a folder path") -> Path:
    """`value` as a path, or `ConfigError` naming `what` (an empty path is refused)."""
    if isinstance(value, str | os.PathLike) and os.fspath(value) not in ("", b""):
        return Path(os.fsdecode(os.fspath(value)))
    raise ConfigError(f"{what}: expected {expected}, got {value!r:.60}")


class Run:
    """One simulated run: its scenario, `metrics.json`, `frames.csv` and `events.csv`.

    Made by `uma.run` or `uma.read_run`, not directly. `folder` is where the files are (None
    for a run not saved). `.frames` and `.events` return a new DataFrame at each access.
    """

    def __init__(
        self,
        files: Mapping[str, bytes],
        *,
        folder: Path | None = None,
        scenario: Scenario | None = None,
    ) -> None:
        self._files = {name: bytes(files[name]) for name in RESULT_FILES}
        self.folder = folder
        if scenario is not None:
            self.__dict__["scenario"] = scenario

    def __repr__(self) -> str:
        metrics = self.metrics
        where = f", folder={str(self.folder)!r}" if self.folder is not None else ""
        return (
            f"Run(scenario={metrics.get('scenario')!r}, seed={metrics.get('seed')}, "
            f"frames={metrics.get('frames')}{where})"
        )

    def file_bytes(self, name: str) -> bytes:
        """The bytes of result file `name` (one of `RESULT_FILES`), as `save` writes them."""
        if name not in self._files:
            raise ConfigError(
                f"Run.file_bytes: expected one of {', '.join(RESULT_FILES)}, got {name!r}"
            )
        return self._files[name]

    def _where(self, name: str) -> Path:
        return (self.folder or Path("<run>")) / name

    @property
    def metrics(self) -> dict[str, Any]:
        """`metrics.json` as a dict (a new one at each access)."""
        return json.loads(self._files["metrics.json"].decode("utf-8"))

    @cached_property
    def _frames(self) -> pd.DataFrame:
        from uma.api.tables import frames_frame

        return frames_frame(self._files["frames.csv"], self._where("frames.csv"))

    @cached_property
    def _events(self) -> pd.DataFrame:
        from uma.api.tables import events_frame

        return events_frame(self._files["events.csv"], self._where("events.csv"))

    @property
    def frames(self) -> pd.DataFrame:
        """`frames.csv`: one row per source frame (units in the column names)."""
        return self._frames.copy()

    @property
    def events(self) -> pd.DataFrame:
        """`events.csv`: `time_ms`, `kind`, `detail`, one row per engine or link event."""
        return self._events.copy()

    @cached_property
    def scenario(self) -> Scenario:
        """The resolved scenario of the run, validated from `scenario.yaml` at first access (a
        run read from a folder whose trace files have since moved reads fine until then)."""
        from uma.config.load import load_scenario

        if self.folder is None:
            raise ConfigError(
                "Run.scenario: this run has no scenario and no folder to read it from"
            )
        return load_scenario(self.folder / "scenario.yaml")

    def save(self, folder: str | os.PathLike) -> Path:
        """Write the four result files into `folder`, whole or not at all; returns the folder.

        The folder is replaced whole, as `uma run --out` does: it must be absent, empty or hold
        only results; one holding anything else is refused with `OutputError`, untouched.
        """
        from uma.atomic import atomic_dir, prepare_out_dir
        from uma.metrics.results import RUN_FILES

        out = prepare_out_dir(
            folder_path(folder, "Run.save"), what="Run.save", replaceable=RUN_FILES
        )
        with atomic_dir(out, replaceable=RUN_FILES, what="Run.save") as staging:
            for name, data in self._files.items():
                (staging / name).write_bytes(data)
        return out

    def summary(self) -> str:
        """The lines `uma run` prints after a run (rates, quality, freezes, engine, codecs)."""
        from uma.sim.summary import format_summary

        return format_summary(self.metrics, self.folder or "(not saved)")

    def timeline(self) -> Figure:
        """The timeline `uma report` draws (rates, delay, quality, queues) as a matplotlib Figure."""
        import tempfile

        from uma.report.timeline import timeline_figure

        if self.folder is not None and _same_files(self.folder, self._files):
            return timeline_figure(self.folder)
        with tempfile.TemporaryDirectory(prefix="uma-run-") as tmp:
            for name, data in self._files.items():
                (Path(tmp) / name).write_bytes(data)
            return timeline_figure(tmp)


def _same_files(folder: Path, files: Mapping[str, bytes]) -> bool:
    try:
        return all((folder / name).read_bytes() == data for name, data in files.items())
    except OSError:
        return False


def _read_files(folder: Path) -> dict[str, bytes]:
    """The result files' bytes: each a regular file (a FIFO would block) of bounded size."""
    import stat

    files = {}
    for name in RESULT_FILES:
        path = folder / name
        try:
            if not stat.S_ISREG(path.stat().st_mode):
                raise ConfigError(f"{path}: expected a result file, got a folder or device")
            with path.open("rb") as handle:
                files[name] = handle.read(MAX_FILE_BYTES + 1)
        except FileNotFoundError:
            raise ConfigError(f"{path}: missing; expected the results of a finished run") from None
        except OSError as err:
            raise ConfigError(f"{path}: cannot read ({err.strerror or err})") from None
        if len(files[name]) > MAX_FILE_BYTES:
            raise ConfigError(
                f"{path}: expected at most {MAX_FILE_BYTES} bytes (a result file), got more"
            )
    return files


def read_run(folder: str | os.PathLike) -> Run:
    """The `Run` in a results folder `uma run` (or `Run.save`) wrote.

    Anything else (a missing or damaged file, a sweep's folder) is one `ConfigError` naming the
    file and, where it can, the line.
    """
    from uma.report.results import read_run as check_run_files

    path = folder_path(folder, "uma.read_run")
    if not path.is_dir():
        raise ConfigError(f"{path}: expected a results folder (as `uma run` writes)")
    if (path / "sweep.parquet").exists() or (path / "sweep.csv").exists():
        raise ConfigError(
            f"{path}: a sweep's results folder, not one run's; read its table with "
            f"uma.read_sweep, or one run with uma.read_run on its points/<hash> folder"
        )
    files = _read_files(path)  # first: refuses a FIFO or device before anything reads it
    check_run_files(path)  # line-numbered messages for a damaged frames.csv or events.csv
    run_ = Run(files, folder=path)
    run_.metrics  # noqa: B018  parsed now: a damaged file fails here, not at first use
    run_._frames  # noqa: B018
    run_._events  # noqa: B018
    return run_


def run(
    scenario: str | os.PathLike | Scenario,
    *,
    seed: int | None = None,
    out: str | os.PathLike | None = None,
    overrides: Mapping[str, Any] | None = None,
    progress: bool = False,
    **keys: Any,
) -> Run:
    """Simulate `scenario` (a file path or a `Scenario`), changed by key-path overrides.

    `overrides` maps key paths to values (`{"engine.codec": "vp8", "route[1].trace": "x.csv"}`);
    keyword arguments set top-level keys (`duration_s=6`); `seed` sets `seed`. All are validated
    as the YAML file is, and a bad one is a `ConfigError` naming the key (`uma.run
    (engine.codec): ...`). With `out` the results folder is written too, as `uma run --out`
    writes it (checked before the run starts). With `progress`, a progress bar (tqdm) on stderr.
    """
    from uma.api.overrides import override_pairs, resolve_scenario
    from uma.atomic import prepare_out_dir
    from uma.metrics.results import RUN_FILES

    pairs = override_pairs(overrides, keys)
    if seed is not None:
        pairs.append(("seed", seed))
    resolved = resolve_scenario(scenario, pairs)
    out_dir = None
    if out is not None:
        out_dir = prepare_out_dir(
            folder_path(out, "uma.run(out=...)"), what="uma.run(out=...)", replaceable=RUN_FILES
        )
    if not isinstance(progress, bool):
        raise ConfigError(f"uma.run(progress=...): expected True or False, got {progress!r:.60}")
    return _simulate(resolved, out_dir, progress=progress)


def _simulate(scenario: Scenario, out_dir: Path | None, *, progress: bool = False) -> Run:
    """Run `scenario`; its files written by the CLI's own writer, into `out_dir` or a temp folder."""
    import tempfile

    from uma.sim import run_scenario
    from uma.sim.summary import save_run

    if progress:
        import sys

        from tqdm import tqdm

        with tqdm(unit="frame", desc=scenario.name, file=sys.stderr, leave=False) as bar:

            def told(done: int, total: int) -> None:
                bar.total = total
                bar.update(done - bar.n)

            result = run_scenario(scenario, progress=told)
    else:
        result = run_scenario(scenario)
    if out_dir is not None:
        save_run(result, out_dir)
        return Run(_read_files(out_dir), folder=out_dir, scenario=result.scenario)
    with tempfile.TemporaryDirectory(prefix="uma-run-") as tmp:
        save_run(result, Path(tmp) / "run")
        files = _read_files(Path(tmp) / "run")
    return Run(files, scenario=result.scenario)
