"""Overrides validated as YAML is, each error naming the key; bad arguments are `UmaError`s."""

import keyword
import os
import string
import subprocess
import sys
from pathlib import Path

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import uma
from uma.api.overrides import resolve_scenario
from uma.config import Scenario, load_scenario
from uma.errors import ConfigError, UmaError


def resolve(path, overrides=None, **keys):
    from uma.api.overrides import override_pairs

    return resolve_scenario(path, override_pairs(overrides, keys))


def test_overrides_set_nested_and_top_level_keys(scenario_file):
    scenario = resolve(
        scenario_file,
        {"engine.codec": "vp8", "receiver.playout": "adaptive", "route[1].duration_s": 2},
        duration_s=3,
    )
    assert scenario.engine.codec == "vp8" and scenario.receiver.playout == "adaptive"
    assert scenario.route[1].duration_s == 2 and scenario.duration_s == 3
    assert scenario.name == "tiny" and scenario.seed == 2  # the file's other keys kept


def test_a_scenario_object_takes_overrides_and_stays_as_it_is_without(scenario_file):
    base = load_scenario(scenario_file)
    assert resolve(base) is base
    changed = resolve(base, {"engine.policy": "oracle"}, seed=9)
    assert isinstance(changed, Scenario) and changed.engine.policy == "oracle"
    assert changed.seed == 9 and changed.route == base.route


@pytest.mark.parametrize(
    ("overrides", "keys", "message"),
    [
        ({"engine.codex": "vp8"}, {}, r"^uma.run \(engine.codex\): unknown key 'codex' in engine"),
        ({}, {"durations": 1}, r"^uma.run \(durations\): unknown key 'durations'"),
        ({"engine.codec": "bogus"}, {}, r"^uma.run \(engine.codec\): expected a full-frame codec"),
        ({"receiver.playout": "x"}, {}, r"^uma.run \(receiver.playout\): input should be"),
        ({}, {"duration_s": -1}, r"^uma.run \(duration_s\): input should be greater than 0"),
        ({}, {"seed": -1}, r"^uma.run \(seed\): "),
        ({"route[7].trace": "a.csv"}, {}, r"^uma.run \(route\[7\].trace\): route has no item"),
        ({"route[0].trace": "absent.csv"}, {}, r"^uma.run \(route\[0\].trace\): expected an exist"),
        ({"engine..codec": 1}, {}, r"^uma.run \(engine..codec\): expected a key path"),
        ({"seed": 1}, {"seed": 2}, r"^uma.run \(seed\): given twice"),
        ({3: 1}, {}, r"^uma.run: expected key paths"),
    ],
)
def test_a_bad_override_is_one_config_error_naming_the_key(scenario_file, overrides, keys, message):
    with pytest.raises(ConfigError, match=message) as caught:
        resolve(scenario_file, overrides, **keys)
    assert "\n" not in str(caught.value)


def test_numpy_scalars_and_tuples_are_taken_as_yaml_numbers_and_lists(scenario_file):
    import numpy as np

    scenario = resolve(
        scenario_file,
        {"route": ({"technology": "GSM", "duration_s": np.float32(1.5)},)},
        seed=np.int64(4),
    )
    assert scenario.seed == 4 and type(scenario.seed) is int
    assert scenario.route[0].duration_s == 1.5 and len(scenario.route) == 1


def test_a_bad_key_in_the_file_still_cites_the_file(tmp_path):
    path = tmp_path / "bad.yaml"
    path.write_text("name: bad\nroute:\n  - {technology: 3G, duration_s: -1}\n")
    with pytest.raises(ConfigError, match=r"bad.yaml:3 \(route\[0\].duration_s\)"):
        resolve(path, {"engine.policy": "oracle"})


def test_a_relative_path_override_resolves_against_the_current_folder(
    scenario_file, tmp_path, monkeypatch
):
    here = tmp_path / "elsewhere"
    here.mkdir()
    (here / "t.csv").write_text("time_s,rate_kbps,technology\n0,400,3G\n")
    monkeypatch.chdir(here)
    scenario = resolve(scenario_file, {"route[0].trace": "t.csv"})
    assert scenario.route[0].trace == str(here / "t.csv")


_NAME = st.text(string.ascii_lowercase + "_", min_size=1, max_size=12)


@settings(
    max_examples=40, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture]
)
@given(parts=st.lists(_NAME, min_size=1, max_size=3))
def test_any_key_path_the_schema_lacks_is_refused_naming_it(scenario_file, parts):
    text = ".".join(parts)
    known = {"name", "seed", "description", "duration_s", "source", "sender", "uplink"}
    known |= {"downlink", "route", "feedback", "engine", "receiver", "metrics", "faults"}
    if parts[0] in known or keyword.iskeyword(parts[0]):
        return
    with pytest.raises(ConfigError, match=rf"^uma.run \({text}\): unknown key '{parts[0]}'"):
        resolve(scenario_file, {text: 1})


@pytest.mark.parametrize(
    ("call", "message"),
    [
        (lambda f: uma.run(3), r"^uma.run: expected a scenario file path"),
        (lambda f: uma.run(""), r"^uma.run: expected a scenario file path"),
        (lambda f: uma.run(f.parent / "absent.yaml"), r"absent.yaml: no such file"),
        (lambda f: uma.run(f, overrides=[("seed", 1)]), r"^uma.run: expected overrides= a map"),
        (lambda f: uma.run(f, out=""), r"^uma.run\(out=...\): expected a folder path"),
        (lambda f: uma.run(f, out=f), r"^uma.run\(out=...\): expected a folder for the results"),
        (lambda f: uma.run(f, progress="yes"), r"^uma.run\(progress=...\): expected True or"),
        (lambda f: uma.read_run(None), r"^uma.read_run: expected a folder path"),
        (lambda f: uma.read_run(f), r"expected a results folder"),
        (lambda f: uma.read_sweep(f.parent), r"found no sweep.parquet"),
        (lambda f: uma.read_sweep(3.5), r"^uma.read_sweep: expected a folder path"),
        (lambda f: uma.sweep(f, workers=0), r"^uma.sweep\(workers=...\): expected a positive"),
        (lambda f: uma.sweep(f, workers=True), r"^uma.sweep\(workers=...\): expected a positive"),
        (lambda f: uma.sweep(None), r"^uma.sweep: expected an experiment file path"),
        (lambda f: uma.sweep(f), r"tiny.yaml:2 \(seed\): unknown key, expected one of name"),
    ],
)
def test_bad_input_to_each_function_is_an_uma_error(scenario_file, call, message):
    with pytest.raises(UmaError, match=message) as caught:
        call(scenario_file)
    assert isinstance(caught.value, ValueError | OSError)  # a builtin too, as the CLI's errors
    assert "\n" not in str(caught.value)


def test_import_uma_stays_light():
    code = "import uma, sys; print('pandas' in sys.modules, 'simpy' in sys.modules, 'av' in sys.modules)"
    root = Path(uma.__file__).parents[1]
    env = {**os.environ, "PYTHONPATH": str(root)}
    out = subprocess.run(
        [sys.executable, "-c", code], capture_output=True, text=True, check=True, env=env, cwd=root
    )
    assert out.stdout.split() == ["False", "False", "False"]


def test_the_api_names_are_public_and_lazy():
    assert {"run", "read_run", "sweep", "read_sweep", "Run"} <= set(uma.__all__)
    assert {"run", "Run"} <= set(dir(uma))
    assert uma.run is uma.api.run and uma.Run is uma.api.Run
    with pytest.raises(AttributeError, match="no attribute 'bogus'"):
        uma.bogus  # noqa: B018
