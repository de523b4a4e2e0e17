"""Issue 28, item 13: a bad command-line value is one line, `uma: error: OPTION: ...`, and exit
2, for every sub-command, never argparse's usage block."""

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from uma.cli import main


def run(capsys, argv):
    code = main(argv)
    err = capsys.readouterr().err
    assert code == 2
    assert err.count("\n") == 1 and err.startswith("uma: error: "), err
    return err


@pytest.mark.parametrize(
    "argv, expected",
    [
        (
            ["bench", "codec", "--codec", "bogus"],
            "--codec: expected one of h264, vp8, av1, all, got 'bogus' (uma bench codec --help)",
        ),
        (["bench", "codec", "--frames", "ten"], "--frames: expected an integer, got 'ten'"),
        (["regress", "s.yaml", "--workers", "two"], "--workers: expected an integer, got 'two'"),
        (
            ["sweep", "e.yaml", "--timeout", "soon"],
            "--timeout: expected a number of seconds, got 'soon'",
        ),
        (["sweep"], "the following arguments are required: EXPERIMENT.yaml (uma sweep --help)"),
        (["rnu"], "COMMAND: expected one of bench, describe, regress"),
        (["run", "--what"], "unrecognized arguments: --what"),
    ],
)
def test_bad_values_are_one_line(capsys, argv, expected):
    assert expected in run(capsys, argv)


def _not_int(text: str) -> bool:
    try:
        int(text)
    except ValueError:
        return True
    return False


@settings(deadline=None, max_examples=60)  # file I/O on a loaded machine
@given(text=st.text(min_size=1).filter(_not_int))
def test_any_non_integer_is_one_line(text):
    import contextlib
    import io

    if text.startswith("-"):
        text = "x" + text  # else argparse reads it as an option
    err = io.StringIO()
    with contextlib.redirect_stderr(err):
        code = main(["bench", "codec", f"--frames={text}"])
    assert code == 2
    assert err.getvalue().count("\n") == 1
    assert err.getvalue().startswith("uma: error: --frames: expected an integer, got ")


@pytest.mark.parametrize(
    "argv, expected",
    [
        (["run", "--seed", "100000000000000000000"], "--seed: expected an integer from 0 to 2**63"),
        (["run", "--seed", "-1"], "--seed: expected an integer from 0 to 2**63 - 1, got '-1'"),
        (["bench", "sim", "--seed", "x"], "--seed: expected an integer, got 'x'"),
        (["sweep", "e.yaml", "--workers", "1000"], "--workers: expected 1 to 64 worker processes"),
        (["regress", "s.yaml", "--workers", "0"], "--workers: expected 1 to 64 worker processes"),
        (
            ["sweep", "e.yaml", "--timeout", "inf"],
            "--timeout: expected a number of seconds above 0",
        ),
        (["bench", "headline", "--timeout", "nan"], "--timeout: expected a number of seconds"),
    ],
)
def test_numbers_are_bounded_on_the_command_line(capsys, argv, expected):
    assert expected in run(capsys, argv)


def test_a_seed_set_from_code_is_bounded_too():
    from uma.config import load_scenario

    with pytest.raises(ValueError, match=r"seed: expected an integer from 0 to 2\*\*63 - 1"):
        load_scenario().with_seed(2**64)


def test_a_reader_that_went_away_ends_the_command_quietly():
    """`uma ... --json | head`: stdout's reader closed mid-output; exit 1, no traceback."""
    import os
    import subprocess
    import sys

    # A command that prints more than a pipe holds (as `uma bench links --json` does).
    code = (
        "import sys, uma.cli as cli\n"
        "cli._main = lambda argv: sys.stdout.write('x' * 1_000_000) and 0\n"
        "sys.exit(cli.main([]))"
    )
    read_end, write_end = os.pipe()
    os.close(read_end)  # every write to stdout is EPIPE
    try:
        done = subprocess.run(
            [sys.executable, "-c", code], stdout=write_end, stderr=subprocess.PIPE, text=True,
            check=False,
        )  # fmt: skip
    finally:
        os.close(write_end)
    assert done.returncode == 1 and done.stderr == "", done.stderr
