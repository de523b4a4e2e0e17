"""Property tests for the parsers: exact round trips, and malformed lines always a TraceError
naming the line (never another exception)."""

import math
import re

import numpy as np
import pytest
from hypothesis import HealthCheck, example, given, settings
from hypothesis import strategies as st

# pytest (prepend import mode) puts this folder on sys.path, so the sibling module imports.
from test_trace_bad_inputs import VALID

from uma.errors import TraceError
from uma.traces import LABELS, Trace, read_trace, write_uma_csv
from uma.traces.parsing import TraceText

rates = st.floats(min_value=0, max_value=1e9, allow_nan=False, allow_infinity=False)
widths = st.floats(min_value=1e-6, max_value=1e5, allow_nan=False)


@given(
    steps=st.lists(
        st.tuples(widths, rates, st.sampled_from(("",) + LABELS)), min_size=1, max_size=40
    ),
    source=st.text(max_size=20),
)
@settings(
    max_examples=150, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture]
)
def test_uma_csv_round_trip(tmp_path, steps, source):
    times = np.concatenate(([0.0], np.cumsum([w for w, _, _ in steps])[:-1]))
    duration = float(times[-1] + steps[-1][0])
    if np.any(np.diff(times) <= 0) or not duration > times[-1]:
        return  # float sums collapsed two steps: not a valid trace to begin with
    trace = Trace(times, [r for _, r, _ in steps], tuple(t for _, _, t in steps), duration, source)
    path = tmp_path / "round.csv"
    write_uma_csv(trace, path)
    back = read_trace(path)
    assert back == trace
    assert back.times_s.tobytes() == trace.times_s.tobytes()  # bit for bit, not approximately
    assert back.duration_s == trace.duration_s


FIELDS = [
    "0", "1", "2.5", "-3", "1e400", "nan", "NaN", "inf", "-inf", "1_0", "0x10", "", " ", "abc",
    "Mbits/sec", "bits/sec", "LTE", "HSPA+", "Pigeon", "-", "2019.12.02_09.39.36",
    "2019.02.30_00.00.00", "time_s", "# duration_s=0.5", "\u00b2", "\u0663", "\x00", "\r",
]  # fmt: skip
structured = st.builds(
    lambda parts, sep: sep.join(parts),
    st.lists(st.sampled_from(FIELDS), min_size=1, max_size=7),
    st.sampled_from([",", "\t", " ", ";"]),
)
garbage = st.one_of(structured, st.text(max_size=30)).map(lambda s: s.replace("\n", " "))
FORMATS = sorted(VALID)


def data_line_numbers(text: str) -> list[int]:
    """Line numbers of the lines a reader reads as data: not blank, not a `#` comment."""
    lines = enumerate(text.split("\n"), 1)
    return [n for n, line in lines if line.strip() and not line.lstrip().startswith("#")]


@given(fmt=st.sampled_from(FORMATS), line=garbage, where=st.integers(0, 10))
# a valid line before the comment: the reader names the next data line, not the comment
@example(fmt="uma-csv", line="0,0", where=1)
@settings(
    max_examples=600, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture]
)
def test_a_malformed_line_is_a_trace_error_naming_it(tmp_path, fmt, line, where):
    lines = VALID[fmt].rstrip("\n").split("\n")
    at = where % (len(lines) + 1)
    text = "\n".join(lines[:at] + [line] + lines[at:]) + "\n"
    path = tmp_path / "t.txt"
    path.write_bytes(text.encode("utf-8", "surrogatepass"))
    inserted = at + 1
    try:
        trace = read_trace(path, format=fmt)
    except TraceError as err:
        message = str(err)
        named = re.match(rf"line (\d+) of {re.escape(str(path))}: expected ", message)
        assert named is not None, message
        # The bad line itself, or the next data line (which no longer follows in order), or,
        # when the inserted line duplicates one that may appear once, the later of the two
        # with the inserted one named as the first.
        following = [n for n in data_line_numbers(text) if n > inserted][:1]
        duplicate = f"(the first is line {inserted})" in message
        assert int(named.group(1)) in [inserted, *following] or duplicate, message
    else:
        assert np.all(np.isfinite(trace.rates_kbps)) and trace.rates_kbps.min() >= 0
        assert math.isfinite(trace.duration_s) and trace.duration_s > trace.times_s[-1]


@given(text=st.text(max_size=200))
@settings(
    max_examples=300, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture]
)
def test_any_text_is_a_trace_or_a_trace_error(tmp_path, text):
    path = tmp_path / "any.down"
    path.write_bytes(text.encode("utf-8", "surrogatepass"))
    for fmt in ["auto", *FORMATS]:
        try:
            trace = read_trace(path, format=fmt)
        except TraceError as err:
            assert str(path) in str(err) or "any.down" in str(err)
        else:
            assert np.all(np.isfinite(trace.rates_kbps)) and trace.rates_kbps.min() >= 0


@given(text=st.text(max_size=120), comments=st.booleans())
@example(text="\ufeff\n# c\n\x0c1\r\n2 \n\n3\n4\n5\n6\n7\n", comments=True)
@settings(
    max_examples=300, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture]
)
def test_the_head_is_the_first_lines(tmp_path, text, comments):
    # a format is sniffed from the first lines, read one at a time: they are the full read's
    path = tmp_path / "any.txt"
    path.write_bytes(text.encode("utf-8", "surrogatepass"))
    try:
        every = TraceText(path, comments=comments)
    except TraceError as err:
        with pytest.raises(TraceError) as head_err:
            TraceText(path, comments=comments, limit=6)
        assert str(head_err.value) == str(err)
        return
    assert TraceText(path, comments=comments, limit=6).lines == every.lines[:6]
