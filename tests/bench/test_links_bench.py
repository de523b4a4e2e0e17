"""`uma bench links`: JSON keys on a tiny synthetic trace, bad input as exit 2, the loop."""

from __future__ import annotations

import json

import pytest

from uma.bench.links import ENGINES, ROW_KEYS, median_row
from uma.cli import main


@pytest.fixture
def tiny_trace(tmp_path):
    path = tmp_path / "tiny.csv"
    path.write_text("0,60000\n1,20000\n2,5000\n3,60000\n4,60000\n", encoding="utf-8")
    return path


def test_links_json_has_the_documented_keys(tiny_trace, tmp_path, capsys):
    plot = tmp_path / "links.png"
    args = ["bench", "links", "--trace", str(tiny_trace), "--duration", "0.8", "--json"]
    assert main([*args, "--plot", str(plot), "--quiet"]) == 0
    result = json.loads(capsys.readouterr().out)
    trace = result["traces"]["tiny.csv"]
    assert trace["capacity_kbps_mean"] > 0
    assert set(trace["engines"]) == set(ENGINES)
    for row in trace["engines"].values():
        assert set(ROW_KEYS) <= set(row)
        assert 0 <= row["keyframe_bits_share"] <= 1
    assert trace["published"] == {}
    # The link's own bound sits under every engine's delay (frames are never shown sooner).
    assert set(trace["bound"]) == {"40", "1200"}
    least_p95_ms = min(row["delay_p95_ms"] for row in trace["engines"].values())
    assert 0 < trace["bound"]["40"]["delay_p95_ms"] <= trace["bound"]["1200"]["delay_p95_ms"]
    assert trace["bound"]["1200"]["delay_p95_ms"] <= least_p95_ms
    assert set(result["median"]) == set(ENGINES)
    assert plot.stat().st_size > 0


@pytest.mark.parametrize(
    "args, expected",
    [
        (["--trace", "/no/such/trace"], "--trace"),
        (["--duration", "0"], "--duration"),
        (["--workers", "0"], "--workers"),
    ],
)
def test_links_bad_input_is_one_line_and_exit_2(args, expected, tiny_trace, capsys):
    full = ["bench", "links", *args] + ([] if "--trace" in args else ["--trace", str(tiny_trace)])
    assert main(full) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and expected in err[0]


def test_links_malformed_trace_is_one_line_and_exit_2(tmp_path, capsys):
    bad = tmp_path / "bad.csv"
    bad.write_text("0,1000\n1,-5\n", encoding="utf-8")
    assert main(["bench", "links", "--trace", str(bad)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "bad.csv" in err[0]


def test_a_trace_too_short_for_one_frame_is_one_line_before_any_run(tmp_path, capsys):
    short = tmp_path / "short.down"  # Mahimahi: three delivery opportunities in 1 ms
    short.write_text("0\n0\n1\n", encoding="utf-8")
    plot = tmp_path / "links.png"
    assert main(["bench", "links", "--trace", str(short), "--plot", str(plot), "--quiet"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and f"--trace {short}" in err[0] and "holds no frame" in err[0], err
    assert not plot.exists()


def test_a_trace_longer_than_a_route_segment_runs_its_first_part(tmp_path, capsys):
    long = tmp_path / "long.csv"  # NYU-METS rows, 4 h 10 min: BB62 rides six hours
    long.write_text("2,Mbits/sec\n" * 15_000, encoding="utf-8")
    args = ["bench", "links", "--trace", str(long), "--duration", "0.5", "--json", "--quiet"]
    assert main(args) == 0, capsys.readouterr().err
    trace = json.loads(capsys.readouterr().out)["traces"]["long.csv"]
    assert trace["duration_s"] == 0.5 and trace["capacity_kbps_mean"] == 2000.0


def test_median_row_skips_missing_values():
    rows = [dict.fromkeys(ROW_KEYS, 1.0), dict.fromkeys(ROW_KEYS, 3.0), dict.fromkeys(ROW_KEYS)]
    assert median_row(rows) == dict.fromkeys(ROW_KEYS, 2.0)


def test_links_loop_on_a_given_trace(tiny_trace, capsys):
    args = ["bench", "links", "--loop", "--trace", str(tiny_trace), "--duration", "4", "--json"]
    assert main(args) == 0
    result = json.loads(capsys.readouterr().out)["loop"]["given"]
    rows = result["traces"]["tiny.csv"]
    assert set(rows) == {"uma", "gcc", "webrtc", "oracle"}
    assert all(row["delay_p95_ms"] >= 20.0 for row in rows.values())  # one way at least
