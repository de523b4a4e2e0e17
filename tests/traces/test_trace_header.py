"""A header row over a header-less format: skipped when its units agree, refused at line 1 when
they do not (a kbit/s column read as bytes/s would be a rate off by 8)."""

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

# pytest (prepend import mode) puts this folder on sys.path, so the sibling module imports.
from test_trace_bad_inputs import VALID, write

from uma.errors import TraceError
from uma.traces import read_trace
from uma.traces.header import column_unit, is_header

HEADERS = {
    "mahimahi": "time_ms",
    "pensieve": "time_s\tMbit/s",
    "hsdpa-log": "unix_s ms_since_start lat lon bytes interval_ms",
    "bytes-per-sec": "timeInSeconds,BytesPerSecond",
    "nyu-mets": "value,unit",
    "nyu-mets-multivariate": "throughput,neighbors,echng,rsrp,rsrq,ta,speed,band",
}


@pytest.mark.parametrize("fmt", sorted(HEADERS))
def test_a_header_row_is_skipped(tmp_path, fmt):
    plain = read_trace(write(tmp_path, VALID[fmt], "plain.txt"))
    headed = write(tmp_path, HEADERS[fmt] + "\r\n" + VALID[fmt])
    assert read_trace(headed) == plain
    assert read_trace(headed, format=fmt) == plain


@pytest.mark.parametrize(
    "text, message",
    [
        (
            "time,kbps\n1,1500\n2,2500\n",
            r"column 2 of the header in bytes/s.*got 'kbps' \(kbit/s\)",
        ),
        ("time_ms\tMbps\n0\t1.5\n1000\t2\n", r"column 1 of the header in s.*got 'time_ms' \(ms\)"),
        ("sec,MB/s\n1,1000\n2,3000\n", r"column 2 .*in bytes/s.*got 'MB/s' \(MB/s\)"),
        ("seconds\n0\n5\n", r"column 1 of the header in ms, as mahimahi rows hold it"),
        ("a,b,c\n1,1000\n2,3000\n", r"a header of 2 columns .*got 3: 'a,b,c'"),
    ],
)
def test_a_header_naming_other_units_is_refused_at_line_1(tmp_path, text, message):
    with pytest.raises(TraceError, match=r"^line 1 of .*trace.txt: expected " + message):
        read_trace(write(tmp_path, text))


def test_the_header_unit_picks_the_reader_not_the_separator(tmp_path):
    # Without the header, commas mean bytes per second; the header says Mbit/s.
    mbps = read_trace(write(tmp_path, "time_s,Mbit/s\n0,1.5\n1,2.5\n2,0\n"))
    assert mbps.rates_kbps.tolist() == [1500.0, 2500.0, 0.0]
    per_sec = read_trace(write(tmp_path, "sec\tbytes_per_sec\n1\t1000\n2\t3000\n"))
    assert per_sec.rates_kbps.tolist() == [8.0, 24.0]


def test_column_units_and_headers():
    units = {
        "time_ms": "ms",
        "timeInSeconds": "s",
        "bytes_per_sec": "bytes/s",
        "rate (Mbit/s)": "Mbit/s",
        "kbps": "kbit/s",
        "MBps": "MB/s",
        "bandwidth": None,
    }
    assert {name: column_unit(name) for name in units} == units
    assert is_header("value,unit") and is_header("time_s\tMbps")
    assert not any(map(is_header, ["13.9,Mbits/sec", "# note", "0", "nan,inf", ""]))


@given(
    rows=st.lists(
        st.tuples(st.integers(1, 10), st.floats(0, 1e3, allow_nan=False)), min_size=1, max_size=30
    )
)
@settings(max_examples=60, suppress_health_check=[HealthCheck.function_scoped_fixture])
def test_any_pensieve_trace_reads_the_same_under_its_header(tmp_path, rows):
    t, lines = 0, []
    for step, mbps in rows:
        t += step
        lines.append(f"{t}\t{mbps!r}")
    body = "\n".join(lines) + "\n"
    plain = read_trace(write(tmp_path, body, "plain.txt"), format="pensieve")
    headed = write(tmp_path, "time_s\tMbit/s\n" + body)
    assert read_trace(headed) == plain
