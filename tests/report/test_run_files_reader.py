"""A run folder's files damaged (truncated, bit-flipped, foreign bytes): `read_run` answers with
the run or one `ConfigError` line, never another exception."""

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from uma.errors import ConfigError
from uma.metrics.results import write_results
from uma.report.results import read_run

FRAMES = "frame,capture_ms,display_ms,frozen,psnr_db\n" + "".join(
    f"{i},{i * 40.0},{i * 40.0 + 120.0},{i % 2},{30 + i / 10}\n" for i in range(12)
)
EVENTS = 'time_ms,kind,detail\n0.000,handover,"3G -> GPRS"\n40.000,switch,"rung 2"\n'
NAMES = ("frames.csv", "events.csv", "metrics.json")


@pytest.fixture(scope="module")
def run_files(tmp_path_factory):
    folder = write_results(
        tmp_path_factory.mktemp("run") / "R",
        scenario_yaml="name: x\n",
        metrics={"freeze_ratio": 0.5, "frames": 12},
        frames_csv=FRAMES,
        events_csv_text=EVENTS,
    )
    return {name: (folder / name).read_bytes() for name in NAMES}


def test_the_run_reads_back(tmp_path, run_files):
    for name, data in run_files.items():
        (tmp_path / name).write_bytes(data)
    run = read_run(tmp_path)
    assert run.metrics["frames"] == 12 and len(run.frames["capture_ms"]) == 12
    assert run.events[0] == (0.0, "handover", "3G -> GPRS")


def test_a_truncated_metrics_file_says_truncated(tmp_path, run_files):
    for name, data in run_files.items():
        (tmp_path / name).write_bytes(data)
    (tmp_path / "metrics.json").write_bytes(run_files["metrics.json"][:-8])
    with pytest.raises(ConfigError, match=r"metrics.json:\d+: .*got truncated JSON"):
        read_run(tmp_path)


@settings(
    max_examples=50, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture]
)
@given(
    name=st.sampled_from(NAMES),
    kind=st.sampled_from(["cut", "flip", "foreign"]),
    where=st.floats(0, 1),
    junk=st.binary(max_size=200),
)
def test_damaged_run_files_are_the_run_or_one_line(tmp_path, run_files, name, kind, where, junk):
    for each, data in run_files.items():
        (tmp_path / each).write_bytes(data)
    data = bytearray(run_files[name])
    at = min(int(where * len(data)), len(data) - 1)
    if kind == "cut":
        data = data[:at]
    elif kind == "flip":
        data[at] ^= 1 << (len(junk) % 8)
    else:
        data = bytearray(junk)
    (tmp_path / name).write_bytes(bytes(data))
    try:
        read_run(tmp_path)
    except ConfigError as err:
        assert "\n" not in str(err), str(err)


@settings(
    max_examples=60, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture]
)
@given(data=st.binary(max_size=300) | st.text(max_size=200).map(str.encode))
def test_read_metrics_is_a_mapping_or_one_line(tmp_path, data):
    from uma.metrics.results import read_metrics

    (tmp_path / "metrics.json").write_bytes(data)
    try:
        assert isinstance(read_metrics(tmp_path / "metrics.json"), dict)
    except ConfigError as err:
        assert "\n" not in str(err) and "metrics.json" in str(err), str(err)
