"""A plain Mahimahi file is parsed in one pass, never split into a list of lines: the trace is
the line-by-line reader's to the bit, and any other file gets that reader's own complaint."""

import gzip
import math

import numpy as np
import pytest
from hypothesis import HealthCheck, example, given, settings
from hypothesis import strategies as st

from uma.errors import TraceError
from uma.traces import Trace, read_mahimahi, read_trace, readers, sniff_format
from uma.traces.parsing import TraceFile, TraceText
from uma.traces.read import _strip_header


def line_by_line(path, *, bin_ms):
    """read_trace(path, format="mahimahi") as it was: every line in a list, the line-by-line
    reader's errors, and its bins as it counted them (all stamps at once)."""
    TraceText(path, comments=True)  # a file of comments only: 'no samples (no data lines)'
    text = TraceText(path)
    _strip_header(text, "mahimahi")
    read_mahimahi(text, bin_ms=bin_ms)  # raises what is wrong, naming the line
    # float() as int() then float would, and past int()'s 4,300 digits too
    ms = np.array([float(line) for _, line in text.lines])
    period_ms = float(ms[-1])
    bins = math.ceil(period_ms / bin_ms)
    index = np.minimum((np.mod(ms, period_ms) // bin_ms).astype(np.int64), bins - 1)
    counts = np.bincount(index, minlength=bins)
    starts_ms = np.arange(bins) * bin_ms
    rates = counts * 12000 / np.minimum(bin_ms, period_ms - starts_ms)
    return Trace(starts_ms / 1000.0, rates, ("",) * bins, period_ms / 1000.0, path.name)


def outcome(read, *args, **options):
    """What a read gives, comparable bit for bit: a trace's arrays as bytes, or the error."""
    try:
        trace = read(*args, **options)
    except TraceError as err:
        return "TraceError", str(err)
    except (ValueError, TypeError) as err:  # none expected: compared, so one would show
        return type(err).__name__, str(err)
    if isinstance(trace, str):  # a format's name
        return trace
    return (
        trace.times_s.tobytes(),
        trace.rates_kbps.tobytes(),
        trace.duration_s,
        trace.technologies,
        trace.source,
    )


# Lines that are not a plain stamp; none reads as a header (that is test_trace_header's).
ODD = [
    "+5", "-3", "1.5", "1e3", "nan", "inf", "# note", "1 2", "1\t2", "1\r2", "\u0663",
    "\x1c5", "\u00a05", "5\x1c", "1_0", "0" * 30 + "7", str(2**53), str(2**53 + 1),
    str(2**63 + 5), "9" * 25, "\ufeff5",
]  # fmt: skip
BLANKS = st.sampled_from(["", "", "", " ", "\t", "  \t", "\x0b", "\x0c", "\r"])


@st.composite
def mahimahi_texts(draw):
    """Mostly plain Mahimahi text (stamps in order), with the odd blank, CRLF, BOM, leading
    zero, stamp that goes back, huge number or line that is no stamp at all."""
    steps = draw(st.lists(st.integers(0, 40) | st.integers(-5, 10**6), min_size=1, max_size=60))
    stamps = np.cumsum(steps).tolist()
    lines = [draw(st.sampled_from(["", "", "0", "00"])) + str(s) for s in stamps]
    if draw(st.booleans()):
        lines = [draw(BLANKS) + line + draw(BLANKS) for line in lines]
    for _ in range(draw(st.integers(0, 3))):
        lines.insert(draw(st.integers(0, len(lines))), draw(st.sampled_from(["", " ", "\r"])))
    if draw(st.integers(0, 3)) == 0:
        lines.insert(draw(st.integers(0, len(lines))), draw(st.sampled_from(ODD)))
    end = draw(st.sampled_from(["\n", "\n", "\r\n", "\r"]))
    text = end.join(lines) + draw(st.sampled_from(["", end, end * 2, " "]))
    return draw(st.sampled_from(["", "\ufeff"])) + text


@given(
    text=mahimahi_texts(),
    bin_ms=st.sampled_from([100.0, 100, 7.3, 1, 0.5, 1e7, 1e30, 0.0, float("nan")]),
    packed=st.booleans(),
    chunk=st.sampled_from([3, 2**20]),
)
@example(text="0\n5\n4\n", bin_ms=100.0, packed=False, chunk=3)
@example(text="0\n0\n", bin_ms=100.0, packed=False, chunk=3)
@example(text="0\n2233720368547\n", bin_ms=100.0, packed=False, chunk=3)
@example(text="\ufeff0\r\n3\r\n\r\n3\r\n25\r\n", bin_ms=10, packed=True, chunk=3)
@example(text="0 \n 3\t\n\x0c10", bin_ms=100.0, packed=False, chunk=2**20)
@example(text="0\n" + "0" * 5000 + "5\n", bin_ms=100.0, packed=False, chunk=2**20)
@example(text="0\n" + "9" * 25 + "\n", bin_ms=1e30, packed=False, chunk=2**20)
@settings(
    max_examples=250, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture]
)
def test_one_pass_reads_as_line_by_line(tmp_path, text, bin_ms, packed, chunk):
    path = tmp_path / "trace.down"
    data = text.encode("utf-8")
    path.write_bytes(gzip.compress(data) if packed else data)
    with pytest.MonkeyPatch.context() as patch:
        patch.setattr(readers, "_CHUNK", chunk)  # stamps binned a few at a time, too
        expected = outcome(line_by_line, path, bin_ms=bin_ms)
        assert outcome(read_trace, path, format="mahimahi", bin_ms=bin_ms) == expected
        if outcome(sniff_format, path) == "mahimahi":
            assert outcome(read_trace, path, bin_ms=bin_ms) == expected
        direct = outcome(read_mahimahi, path, bin_ms=bin_ms)
        if math.isfinite(bin_ms) and bin_ms > 0:  # else refused before the file is read
            assert direct == outcome(lambda: read_mahimahi(TraceText(path), bin_ms=bin_ms))
        else:
            assert direct[1] == f"mahimahi bin_ms: expected a duration > 0 ms, got {bin_ms!r}"


def test_a_plain_file_is_never_split_into_lines(tmp_path, monkeypatch):
    path = tmp_path / "plain.down"
    path.write_text("0\n3\n3\n10\n25\n")
    expected = read_trace(path)

    def refuse(self):
        raise AssertionError("the whole text decoded and split")

    monkeypatch.setattr(TraceFile, "decoded", refuse)
    assert read_trace(path) == expected and read_mahimahi(path) == expected
    path.write_text("0\n-3\n")
    with pytest.raises(AssertionError, match="split"):  # the line-by-line reader names a line
        read_trace(path)


def test_a_stamp_past_int_s_digit_limit_is_one_line_not_a_traceback(tmp_path):
    # int() refuses more than 4,300 digits with a ValueError, which escaped as a traceback
    from uma.errors import TraceError

    path = tmp_path / "long.down"
    path.write_text("1\n2\n" + "9" * 5000 + "\n")
    with pytest.raises(TraceError, match=r"line 3 of .*long\.down: expected a finite delivery"):
        read_trace(path)
    padded = tmp_path / "padded.down"  # leading zeros: the number is 3
    padded.write_text("1\n2\n" + "0" * 5000 + "3\n")
    assert read_trace(padded).duration_s == pytest.approx(0.003)
