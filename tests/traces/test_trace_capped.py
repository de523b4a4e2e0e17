"""Issue 28, item 6: every trace read is capped (size before and after gzip), and what is no
regular file is refused in one line rather than read without end."""

import gzip
import os

import pytest

from uma.errors import TraceError
from uma.traces import read_trace
from uma.traces.parsing import MAX_TRACE_BYTES


def test_a_gzip_bomb_is_refused_while_expanding(tmp_path, monkeypatch):
    """Refused after expanding at most the cap and a byte, never the whole bomb (counted on
    zlib's own output, not timed)."""
    import zlib

    path = tmp_path / "bomb.log.gz"
    path.write_bytes(gzip.compress(b"0" * (2 * MAX_TRACE_BYTES), compresslevel=9))
    assert path.stat().st_size < 2**20
    expanded = []
    real = zlib.decompressobj

    class Counting:
        def __init__(self, *args, **kwargs):
            self._inner = real(*args, **kwargs)

        def __getattr__(self, name):
            return getattr(self._inner, name)

        def decompress(self, data, max_length=0):
            out = self._inner.decompress(data, max_length)
            expanded.append(len(out))
            return out

    monkeypatch.setattr(zlib, "decompressobj", Counting)
    with pytest.raises(TraceError, match=r"bomb\.log\.gz: decompresses to more than 67108864"):
        read_trace(path)
    assert 0 < sum(expanded) <= MAX_TRACE_BYTES + 1


def test_gzip_members_are_all_read_and_a_truncated_one_named(tmp_path):
    path = tmp_path / "two.csv.gz"
    path.write_bytes(gzip.compress(b"1,100\n2,200\n") + gzip.compress(b"3,300\n4,400\n"))
    assert len(read_trace(path, format="bytes-per-sec").rates_kbps) >= 3
    whole = gzip.compress(b"1,100\n" * 1000)
    path.write_bytes(whole[: len(whole) - 12])
    with pytest.raises(TraceError, match=r"does not decompress \(truncated\)"):
        read_trace(path)


@pytest.mark.parametrize("device", ["/dev/zero", "/dev/urandom"])
def test_a_device_is_refused(device):
    with pytest.raises(TraceError, match=rf"^{device}: expected a trace file .*character device"):
        read_trace(device)


def test_a_fifo_and_a_symlink_loop_are_refused(tmp_path):
    os.mkfifo(tmp_path / "fifo")
    with pytest.raises(TraceError, match="got a FIFO"):
        read_trace(tmp_path / "fifo")
    (tmp_path / "loop").symlink_to(tmp_path / "loop")
    with pytest.raises(TraceError, match=r"loop: a symlink loop, expected a trace file"):
        read_trace(tmp_path / "loop")


def test_a_huge_trace_is_refused_before_reading(tmp_path):
    path = tmp_path / "huge.csv"
    with open(path, "wb") as handle:
        handle.truncate(MAX_TRACE_BYTES + 1)
    with pytest.raises(TraceError, match="above the maximum 64 MiB for a trace file"):
        read_trace(path)
