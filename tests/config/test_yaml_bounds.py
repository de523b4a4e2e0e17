"""Issue 28, items 5-6: YAML that expands without bound, nests without end, or is no file at
all is refused in one line naming the file, quickly and within memory."""

import gzip
import os
import re

import pytest
from hypothesis import example, given, settings
from hypothesis import strategies as st

from uma.config import load_scenario
from uma.config.yamlfile import MAX_YAML_DEPTH, load_yaml
from uma.errors import ConfigError

MINIMAL = "name: demo\nroute:\n  - {technology: WLAN, duration_s: 10}\n"


def laughs(levels: int = 9) -> str:
    """The billion laughs: each level a list of ten aliases of the one below (10**levels)."""
    lines = ['a0: &a0 "lol"']
    for level in range(1, levels + 1):
        below = ", ".join([f"*a{level - 1}"] * 10)
        lines.append(f"a{level}: &a{level} [{below}]")
    return "\n".join(lines) + "\n"


def test_an_alias_bomb_is_refused_before_it_is_built(tmp_path, monkeypatch):
    """Refused on the composed nodes (each counted once), before any Python object is built
    (a hang would build 10**9): checked by construction failing, not by a clock."""
    import yaml.constructor

    def never(*args, **kwargs):
        raise AssertionError("the document was constructed")

    monkeypatch.setattr(yaml.constructor.BaseConstructor, "construct_document", never)
    path = tmp_path / "bomb.yaml"
    path.write_text(laughs().replace("a", "x") + MINIMAL + "description: *x9\n")
    with pytest.raises(ConfigError, match=r"bomb\.yaml: expands to more than 200000 values"):
        load_scenario(path)


def test_many_aliases_are_refused_naming_the_line(tmp_path):
    path = tmp_path / "aliases.yaml"
    path.write_text("x: &x 1\nys:\n" + "  - *x\n" * 1001)
    with pytest.raises(ConfigError, match=r"aliases\.yaml:1003: more than 1000 aliases"):
        load_yaml(path)


def test_a_few_anchors_still_work(tmp_path):
    path = tmp_path / "ok.yaml"
    path.write_text("seg: &seg {technology: WLAN, duration_s: 1}\nroute: [*seg, *seg]\n")
    data, _ = load_yaml(path)
    assert data["route"] == [{"technology": "WLAN", "duration_s": 1}] * 2


@settings(deadline=None, max_examples=20)  # file I/O on a loaded machine
@given(depth=st.integers(1, 3 * MAX_YAML_DEPTH), kind=st.sampled_from(["list", "map"]))
@example(depth=MAX_YAML_DEPTH - 1, kind="list").via("the deepest accepted")
@example(depth=MAX_YAML_DEPTH, kind="map").via("the shallowest refused")
def test_nesting_is_read_up_to_its_bound_and_refused_beyond(tmp_path_factory, depth, kind):
    path = tmp_path_factory.mktemp("deep") / "deep.yaml"
    text = "[" * depth + "]" * depth if kind == "list" else "{a: " * depth + "1" + "}" * depth
    path.write_text(f"x: {text}\n")  # the top mapping is one level more
    if depth + 1 <= MAX_YAML_DEPTH:
        load_yaml(path)
    else:
        with pytest.raises(ConfigError, match=r"deep\.yaml:1: nested more than 64 levels deep"):
            load_yaml(path)


def test_a_thousand_deep_nesting_is_one_line(tmp_path):
    path = tmp_path / "deep.yaml"
    path.write_text("route: " + "[" * 1000 + "]" * 1000 + "\n")
    with pytest.raises(ConfigError, match="nested more than 64 levels deep"):
        load_scenario(path)


def test_a_fifo_or_device_is_refused_without_blocking(tmp_path):
    fifo = tmp_path / "s.yaml"
    os.mkfifo(fifo)
    with pytest.raises(
        ConfigError, match=r"s\.yaml: expected a file \(a regular file\), got a FIFO"
    ):
        load_scenario(fifo)
    for device in ("/dev/zero", "/dev/urandom"):
        with pytest.raises(ConfigError, match="got a character device"):
            load_scenario(device)


def test_a_huge_file_is_refused_before_reading(tmp_path):
    path = tmp_path / "big.yaml"
    with open(path, "wb") as handle:
        handle.truncate(9 * 2**20)
    with pytest.raises(ConfigError, match=r"big\.yaml: 9437184 bytes, above the maximum 8 MiB"):
        load_scenario(path)


@pytest.mark.parametrize("key", ["route[0].trace", "engine.ladder", "engine.mbc.description"])
def test_a_symlink_loop_named_by_a_scenario_is_one_line(tmp_path, key):
    (tmp_path / "loop").symlink_to(tmp_path / "loop")
    text = {
        "route[0].trace": "name: x\nroute:\n  - {technology: 3G, duration_s: 1, trace: loop}\n",
        "engine.ladder": MINIMAL + "engine: {ladder: loop}\n",
        "engine.mbc.description": MINIMAL + "engine: {mbc: {description: loop}}\n",
    }[key]
    path = tmp_path / "s.yaml"
    path.write_text(text)
    where = re.escape(f"({key}): expected an existing file, got ")
    with pytest.raises(ConfigError, match=rf"{where}.*loop' \(a symlink loop\)"):
        load_scenario(path)
    with pytest.raises(ConfigError, match="a symlink loop"):
        load_scenario(tmp_path / "loop")


def test_a_named_fifo_is_refused(tmp_path):
    os.mkfifo(tmp_path / "trace.csv")
    path = tmp_path / "s.yaml"
    path.write_text("name: x\nroute:\n  - {technology: 3G, duration_s: 1, trace: trace.csv}\n")
    with pytest.raises(ConfigError, match=r"route\[0\]\.trace\): expected a regular file"):
        load_scenario(path)


def test_a_gzip_scenario_is_not_expanded(tmp_path):
    path = tmp_path / "s.yaml"
    path.write_bytes(gzip.compress(MINIMAL.encode()))
    with pytest.raises(ConfigError, match="cannot read as UTF-8 text"):
        load_scenario(path)
