"""Published figures per trace: the CSV reader, trace matching, and `uma bench salsify --trace`."""

import json

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from uma.bench.published import published_for, read_published, trace_name
from uma.cli import main
from uma.errors import ConfigError

CSV = """# a comment
trace,system,delay_mean_ms,delay_p95_ms,ssim_db_mean
ATT-LTE-driving,salsify_1c,349.09,448.51,15.4096
ATT-LTE-driving,webrtc,934.69,4729.94,13.3534
TMobile-UMTS-driving,salsify_1c,,3907,13.2
"""


def test_rows_by_trace_and_system(tmp_path):
    path = tmp_path / "p.csv"
    path.write_text(CSV)
    table = read_published(path)
    assert table["att-lte-driving"]["webrtc"] == {"delay_p95_ms": 4729.94, "ssim_db": 13.3534}
    assert published_for("x/TMobile-UMTS-driving.down", path) == {
        "salsify_1c": {"delay_p95_ms": 3907.0, "ssim_db": 13.2}
    }
    assert published_for("Verizon-LTE-short.down", path) == {}
    assert published_for("ATT-LTE-driving.down", tmp_path / "absent.csv") == {}


def test_trace_names_lose_direction_and_compression():
    assert trace_name("/a/TMobile-UMTS-driving.down") == "TMobile-UMTS-driving"
    assert trace_name("ATT-LTE-driving.up.gz") == "ATT-LTE-driving"
    assert trace_name(".down") == ".down"


@pytest.mark.parametrize(
    "text, where",
    [
        ("trace,system\nA,b\n", ":1: expected columns"),
        ("trace,system,delay_p95_ms,ssim_db_mean\nA,b,1\n", ":2: expected 4 fields"),
        ("trace,system,delay_p95_ms,ssim_db_mean\nA,b,x,1\n", ":2: delay_p95_ms"),
        ("trace,system,delay_p95_ms,ssim_db_mean\nA,b,nan,1\n", ":2: delay_p95_ms"),
        ("trace,system,delay_p95_ms,ssim_db_mean\nA,b,1,1\nA,b,2,2\n", ":3: A b given twice"),
        ("# only comments\n", "no lines"),
    ],
)
def test_a_malformed_file_names_its_line(tmp_path, text, where):
    path = tmp_path / "p.csv"
    path.write_text(text)
    with pytest.raises(ConfigError, match=where):
        read_published(path)


@settings(max_examples=60, deadline=None)
@given(st.binary(max_size=200))
def test_any_bytes_are_figures_or_one_line_error(tmp_path_factory, data):
    path = tmp_path_factory.mktemp("p") / "p.csv"
    path.write_bytes(CSV.encode()[: len(data)] + data)
    try:
        table = read_published(path)
    except ConfigError as err:
        assert "\n" not in str(err) and str(path) in str(err)
    else:
        for systems in table.values():
            for row in systems.values():
                assert set(row) == {"delay_p95_ms", "ssim_db"}


def test_salsify_on_another_trace_is_named_after_it_with_nothing_published(capsys, shared_data):
    pytest.importorskip("aiortc")
    trace = shared_data / "traces" / "mahimahi" / "Verizon-LTE-short.down"
    if not trace.is_file():
        pytest.skip("no Verizon-LTE-short trace")
    # Only the naming is checked here (tests/bench/test_bench_smoke.py checks the rows): 5 frames.
    argv = ["bench", "salsify", "--trace", str(trace), "--frames", "5", "--clip-frames", "5"]
    assert main([*argv, "--skip-default", "--json"]) == 0
    result = json.loads(capsys.readouterr().out)
    assert result["scenario"] == "salsify-verizon-lte-short"
    assert result["trace_name"] == "Verizon-LTE-short"
    assert result["published"] == {}
    assert result["targets"]["delay_between_salsify_and_webrtc"] is None


def test_a_bad_published_file_is_exit_2(tmp_path, capsys, shared_data):
    bad = tmp_path / "p.csv"
    bad.write_text("trace,system\n")
    assert main(["bench", "salsify", "--published", str(bad), "--frames", "5"]) == 2
    err = capsys.readouterr().err
    assert f"{bad}:1: expected columns" in err and err.count("\n") == 1
