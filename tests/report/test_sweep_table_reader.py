"""`uma report SWEEP_DIR` on a damaged sweep.csv: one line naming the file and line, exit 2.

Property tests feed the reader truncated, bit-flipped and foreign bytes: it answers with the
table or with one `ConfigError` line, never another exception."""

import re

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from uma.cli import main
from uma.errors import ConfigError
from uma.experiments.table import write_table
from uma.report.sweep_plot import sweep_series
from uma.report.sweep_table import read_sweep_table


def _rows():
    rows = [
        {"point": i, "hash": f"h{i:015d}", "repeat": r, "engine.policy": policy,
         "receiver.playout_delay_ms": delay, "seed": r, "status": "ok", "error": "",
         "freeze_ratio": 0.1 * i + 0.01 * r, "video": "96x64@25"}
        for i, (policy, delay) in enumerate(
            [(p, d) for p in ("throughput", "oracle") for d in (150, 300)]
        )
        for r in range(2)
    ]  # fmt: skip
    rows[-1] |= {"status": "failed", "freeze_ratio": None, "error": "TraceError: bad, line 2"}
    rows[-2] |= {"status": "missing", "freeze_ratio": None}
    return rows


@pytest.fixture(scope="module")
def good_table(tmp_path_factory):
    folder = tmp_path_factory.mktemp("sweep")
    write_table(_rows(), folder / "sweep.csv", folder / "sweep.parquet")
    return (folder / "sweep.csv").read_bytes()


def test_the_written_table_reads_back(tmp_path, good_table):
    (tmp_path / "sweep.csv").write_bytes(good_table)
    table = read_sweep_table(tmp_path / "sweep.csv")
    assert table.grid_keys == ("engine.policy", "receiver.playout_delay_ms")
    assert [r["status"] for r in table.rows][-2:] == ["missing", "failed"]
    data = sweep_series(tmp_path, metric="freeze_ratio", x="receiver.playout_delay_ms")
    assert (data.runs, data.failed, data.missing, data.repeats) == (8, 1, 1, 2)
    assert data.series[("oracle",)] == {150.0: [pytest.approx(0.2), pytest.approx(0.21)]}


@pytest.mark.parametrize(
    "damage, said",
    [
        (
            lambda b: b[: len(b) - 30],
            r"sweep.csv:9: expected 10 fields, got \d+ \(the table is truncated",
        ),
        (lambda b: b[:-1], r"sweep.csv:9: expected every row to end with a newline"),
        (lambda b: b"", r"sweep.csv:1: expected a header row point,hash,repeat"),
        (
            lambda b: b.replace(b",ok,", b",o\xffk,", 1),
            r"sweep.csv:2: expected UTF-8 text, got byte 0xff",
        ),
        (
            lambda b: b.replace(b",ok,", b",done,", 1),
            r"sweep.csv:2 \(status\): expected one of ok, failed, missing, got 'done'",
        ),
        (
            lambda b: b.replace(b"0.01,", b"0.0x,", 1),
            r"sweep.csv:3 \(freeze_ratio\): expected a number, got '0.0x'",
        ),
        (
            lambda b: b.replace(b"\n", b"\n\0", 1),
            r"sweep.csv:2 \(point\): expected a whole number, got '\\x000'",
        ),
        (lambda b: b"PK\x03\x04" + b[4:], r"sweep.csv:1: expected a header point,hash,repeat"),
    ],
    ids=[
        "truncated-mid-row",
        "last-newline-cut",
        "empty",
        "not-utf8",
        "status",
        "number",
        "nul",
        "foreign",
    ],
)
def test_a_damaged_table_is_one_line_naming_file_and_line(
    tmp_path, capsys, good_table, damage, said
):
    (tmp_path / "sweep.csv").write_bytes(damage(good_table))
    code = main(
        ["report", str(tmp_path), "--metric", "freeze_ratio", "--x", "receiver.playout_delay_ms"]
    )
    err = capsys.readouterr().err
    assert code == 2 and err.count("\n") == 1 and err.startswith("uma: error: "), err
    assert re.search(said, err), err
    assert not list(tmp_path.glob("*.png"))


def _check(folder, data: bytes) -> None:
    (folder / "sweep.csv").write_bytes(data)
    try:
        sweep_series(folder, metric="freeze_ratio", x=None)
    except ConfigError as err:
        message = str(err)
        assert message and "\n" not in message and "\r" not in message, message


FUZZ = settings(
    max_examples=40, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture]
)


@FUZZ
@given(cut=st.floats(0, 1))
def test_any_truncation_is_the_table_or_one_line(tmp_path, good_table, cut):
    _check(tmp_path, good_table[: int(len(good_table) * cut)])


@FUZZ
@given(flips=st.lists(st.tuples(st.floats(0, 1), st.integers(0, 7)), min_size=1, max_size=6))
def test_any_bit_flips_are_the_table_or_one_line(tmp_path, good_table, flips):
    data = bytearray(good_table)
    for where, bit in flips:
        data[min(int(where * len(data)), len(data) - 1)] ^= 1 << bit
    _check(tmp_path, bytes(data))


@FUZZ
@given(data=st.binary(max_size=600) | st.text(max_size=300).map(lambda t: t.encode("utf-8")))
def test_foreign_bytes_are_one_line(tmp_path, data):
    _check(tmp_path, data)


@FUZZ
@given(at=st.floats(0, 1), junk=st.binary(min_size=1, max_size=40))
def test_inserted_bytes_are_the_table_or_one_line(tmp_path, good_table, at, junk):
    cut = int(at * len(good_table))
    _check(tmp_path, good_table[:cut] + junk + good_table[cut:])


def test_the_reader_knows_every_status_the_sweep_writes():
    from uma.experiments.table import STATUSES as WRITTEN
    from uma.report.sweep_table import STATUSES as READ

    assert READ == WRITTEN
