"""Times in ms where seconds are expected: rows a median of more than 100 s apart are refused,
naming a row, instead of a ride stretched 1000 times."""

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from uma.errors import TraceError
from uma.traces import read_trace


def write(tmp_path, text, name="trace.txt"):
    path = tmp_path / name
    path.write_text(text, encoding="utf-8")
    return path


@pytest.mark.parametrize(
    "text, line",
    [
        ("1000,2000\n2000,3000\n3000,1000\n", 2),  # sec,bytes_per_sec
        ("0\t1.5\n1059\t2.0\n2169\t0.5\n", 3),  # pensieve: the first row the median apart
        (
            "Timestamp,NetworkMode,DL_bitrate\n1575279575000,LTE,100\n1575279576000,LTE,50\n",
            3,
        ),  # labelled-csv, unix ms
    ],
)
def test_times_in_ms_are_refused(tmp_path, text, line):
    with pytest.raises(
        TraceError, match=rf"^line {line} of .*: expected times in s, .*are the times in ms\?"
    ):
        read_trace(write(tmp_path, text))


def test_a_slow_sampled_trace_is_still_read(tmp_path):
    fcc = read_trace(write(tmp_path, "0\t0.5\n5\t0.4\n10\t0.6\n"))  # Pensieve's FCC: 5 s apart
    assert fcc.duration_s == 15.0
    one_gap = read_trace(write(tmp_path, "1,1000\n2,1000\n500,1000\n501,1000\n"))
    assert one_gap.duration_s == 501.0  # one outage-long gap is not a median


@given(steps=st.lists(st.integers(1, 3), min_size=1, max_size=40))
@settings(max_examples=50, suppress_health_check=[HealthCheck.function_scoped_fixture])
def test_any_per_second_trace_is_read_in_s_and_refused_in_ms(tmp_path, steps):
    stamps = [sum(steps[: i + 1]) for i in range(len(steps))]
    body = "".join(f"{t},{1000 + t}\n" for t in stamps)
    assert read_trace(write(tmp_path, body)).duration_s == stamps[-1] - stamps[0] + 1
    in_ms = "".join(f"{t * 1000},{1000 + t}\n" for t in stamps)
    if len(stamps) > 1:
        with pytest.raises(TraceError, match="are the times in ms"):
            read_trace(write(tmp_path, in_ms))
