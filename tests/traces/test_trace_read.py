"""Format sniffing: a two-column file's separator picks its unit (commas: bytes per second;
blanks: Mbit/s), so rates no link has mean the other unit was meant: refused, naming the row."""

import pytest

from uma.errors import TraceError
from uma.traces import read_trace, sniff_format


def write(tmp_path, text, name="trace.txt"):
    path = tmp_path / name
    path.write_text(text, encoding="utf-8")
    return path


def test_mbit_per_s_written_with_commas_is_refused_not_read_as_bytes(tmp_path):
    # Before: read as bytes per second, a mean of 0.01 kbit/s instead of 1,000.
    path = write(tmp_path, "0.0,0.48\n5.0,0.4\n10.0,0.6\n15.0,0.5\n")
    assert sniff_format(path) == "bytes-per-sec"
    with pytest.raises(
        TraceError,
        match=r"^line 3 of .*: expected sec,bytes_per_sec \(commas\), whose fastest row should "
        r"carry 1,000 bytes or more \(8 kbit/s\); got at most 0.6 bytes .*header row: time_s,Mbit/s",
    ):
        read_trace(path)
    assert read_trace(path, format="pensieve").rates_kbps.tolist() == [480.0, 400.0, 600.0, 500.0]


def test_bytes_per_second_written_with_a_tab_is_refused_not_read_as_mbit(tmp_path):
    # Before: 125,000 times too fast (or a terabit error naming no line).
    path = write(tmp_path, "1\t20000\n2\t30000\n3\t0\n")
    with pytest.raises(TraceError, match=r"^line 2 of .*at most 10 Gbit/s; got 30000 Mbit/s"):
        read_trace(path)


def test_a_dead_link_and_slow_links_are_read(tmp_path):
    dead = read_trace(write(tmp_path, "1,0\n2,0\n3,0\n"))
    assert dead.rates_kbps.tolist() == [0.0, 0.0, 0.0] and dead.duration_s == 3.0
    gsm = read_trace(write(tmp_path, "1,1200\n2,0\n"))  # 9.6 kbit/s
    assert gsm.rates_kbps.tolist() == [9.6, 0.0]
    fast = read_trace(write(tmp_path, "0\t9000\n1\t0.5\n"))  # 9 Gbit/s is still a link
    assert fast.rates_kbps.tolist() == [9e6, 500.0]
