"""Reports: the timeline PNG of a run, the receiver video, the sweep summary plot, bad input."""

import pytest

from uma.cli import main

SCENARIO = """\
name: tiny
seed: 2
source: {kind: pattern, width: 96, height: 64, fps: 25}
route:
  - {technology: 3G, duration_s: 1.2}
  - {technology: GPRS, duration_s: 1.2}
"""


@pytest.fixture(scope="module")
def run_dir(tmp_path_factory):
    folder = tmp_path_factory.mktemp("report")
    (folder / "s.yaml").write_text(SCENARIO)
    out = folder / "out"
    assert main(["run", str(folder / "s.yaml"), "--out", str(out), "--quiet", "--report"]) == 0
    return out


def png_size(path):
    import struct

    data = path.read_bytes()
    assert data[:8] == b"\x89PNG\r\n\x1a\n"
    return struct.unpack(">II", data[16:24])


def test_run_report_draws_the_timeline(run_dir):
    width, height = png_size(run_dir / "timeline.png")
    assert (width, height) == (1100, 1050)  # five panels


def test_the_delay_panel_draws_the_links_bound_when_the_scenario_loads(run_dir, tmp_path):
    import shutil

    from uma.report.timeline import timeline_figure

    def labels(folder):
        delays = timeline_figure(folder).axes[2]
        return [line.get_label() for line in delays.get_lines()]

    assert labels(run_dir) == ["delay", "least the link allowed (40-byte packets)"]
    moved = tmp_path / "moved"
    shutil.copytree(run_dir, moved)
    (moved / "scenario.yaml").write_text("name: [not, a, scenario\n")
    assert labels(moved) == ["delay"]


def test_video_shows_source_beside_the_display_for_every_instant(run_dir, capsys):
    import av
    import numpy as np

    assert main(["report", str(run_dir), "--video"]) == 0
    assert capsys.readouterr().out.split() == [
        str(run_dir / "timeline.png"),
        str(run_dir / "receiver.mp4"),
    ]
    with av.open(str(run_dir / "receiver.mp4")) as container:
        frames = [f.to_ndarray(format="gray") for f in container.decode(video=0)]
    assert len(frames) == 60 and frames[0].shape == (64, 192)
    # The right half is the displayed picture: close to the source half when not frozen.
    last = frames[-1].astype(float)
    left, right = last[20:, :96], last[20:, 96:]
    assert np.abs(left - right).mean() < np.abs(left - np.roll(left, 7, axis=1)).mean()


def test_sweep_summary_plot(tmp_path, capsys):
    from uma.experiments.table import write_table

    rows = [
        {"point": i, "hash": f"h{i}", "repeat": r, "engine.policy": policy,
         "receiver.playout_delay_ms": delay, "seed": r, "status": "ok", "error": "",
         "freeze_ratio": 0.1 * i + 0.01 * r}
        for i, (policy, delay) in enumerate(
            [(p, d) for p in ("throughput", "oracle") for d in (150, 300, 600)]
        )
        for r in range(2)
    ]  # fmt: skip
    rows[-1] |= {"status": "failed", "freeze_ratio": None}
    write_table(rows, tmp_path / "sweep.csv", tmp_path / "sweep.parquet")
    args = ["report", str(tmp_path), "--x", "receiver.playout_delay_ms"]
    assert main(args) == 0
    assert png_size(tmp_path / "summary-freeze_ratio.png") == (750, 480)
    capsys.readouterr()
    assert main(["report", str(tmp_path), "--metric", "psnr"]) == 2
    assert "has no column 'psnr'" in capsys.readouterr().err
    assert main(["report", str(tmp_path), "--x", "engine.safety"]) == 2
    assert (
        "expected one of the grid's keys engine.policy, receiver.playout_delay_ms"
        in capsys.readouterr().err
    )


def test_report_on_a_folder_without_results_is_exit_2(tmp_path, capsys):
    assert main(["report", str(tmp_path)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "frames.csv: missing" in err[0]
