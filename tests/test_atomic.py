import pytest

from uma.atomic import atomic_write_text


def test_atomic_write_replaces_whole_file(tmp_path):
    target = tmp_path / "out" / "metrics.json"
    atomic_write_text(target, "first")
    atomic_write_text(target, "second")
    assert target.read_text() == "second"
    assert [p.name for p in target.parent.iterdir()] == ["metrics.json"]


def test_crash_while_writing_keeps_old_file(tmp_path):
    from uma.atomic import atomic_open

    target = tmp_path / "metrics.json"
    atomic_write_text(target, "old")
    with pytest.raises(RuntimeError), atomic_open(target) as handle:
        handle.write("half")
        raise RuntimeError("crash")
    assert target.read_text() == "old"
    assert [p.name for p in tmp_path.iterdir()] == ["metrics.json"]


def test_out_dir_that_is_a_file_is_refused_before_any_work(tmp_path):
    from uma.atomic import prepare_out_dir
    from uma.errors import OutputError

    file = tmp_path / "taken"
    file.write_text("x")
    with pytest.raises(
        OutputError, match="expected a folder for the results, got an existing file"
    ):
        prepare_out_dir(file)
    with pytest.raises(OutputError, match="got an existing file"):
        prepare_out_dir(file / "below")
    assert prepare_out_dir(tmp_path / "new" / "deeper") == tmp_path / "new" / "deeper"
    assert not (tmp_path / "new").exists()


def test_write_failure_is_an_output_error(tmp_path):
    from uma.errors import OutputError

    (tmp_path / "metrics.json").mkdir()  # a folder where the file goes
    with pytest.raises(OutputError, match="metrics.json: cannot write"):
        atomic_write_text(tmp_path / "metrics.json", "x")
    assert [p.name for p in tmp_path.iterdir()] == ["metrics.json"]
