"""Issue 28, item 13: a bad command-line value is one line, `uma: error: OPTION: ...`, and exit
2, for every sub-command, never argparse's usage block."""

import pytest
from hypothesis import given
from hypothesis import strategies as st

from uma.cli import main


def run(capsys, argv):
    with pytest.raises(SystemExit) as exit_info:
        main(argv)
    err = capsys.readouterr().err
    assert exit_info.value.code == 2
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
        (["sweep", "e.yaml", "--timeout", "soon"], "--timeout: expected a number, got 'soon'"),
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


@given(text=st.text(min_size=1).filter(_not_int))
def test_any_non_integer_is_one_line(text):
    import contextlib
    import io

    if text.startswith("-"):
        text = "x" + text  # else argparse reads it as an option
    err = io.StringIO()
    with contextlib.redirect_stderr(err), pytest.raises(SystemExit) as exit_info:
        main(["bench", "codec", f"--frames={text}"])
    assert exit_info.value.code == 2
    assert err.getvalue().count("\n") == 1
    assert err.getvalue().startswith("uma: error: --frames: expected an integer, got ")
