import pytest

from uma.config import load_scenario
from uma.errors import ConfigError

MINIMAL = """\
name: demo
route:
  - technology: WLAN
    duration_s: 10
"""


def write(tmp_path, text, name="s.yaml"):
    path = tmp_path / name
    path.write_text(text)
    return path


def test_minimal_scenario_gets_defaults(tmp_path):
    scenario = load_scenario(write(tmp_path, MINIMAL))
    assert scenario.name == "demo"
    assert scenario.run_duration_s == 10
    assert scenario.receiver.playout_delay_ms == 300
    assert scenario.engine.policy == "throughput"


def test_default_scenario_loads():
    scenario = load_scenario()
    assert scenario.name == "stockholm-uppsala"
    techs = {segment.technology for segment in scenario.route}
    assert {"WLAN", "3G", "GPRS", "GSM"} <= techs


def test_unknown_key_names_line_and_path(tmp_path):
    path = write(tmp_path, MINIMAL + "receiver:\n  playout_ms: 300\n")
    with pytest.raises(ConfigError, match=r"s\.yaml:6 \(receiver\.playout_ms\): unknown key"):
        load_scenario(path)


def test_wrong_type_names_key(tmp_path):
    text = MINIMAL.replace("duration_s: 10", 'duration_s: "10 s"')
    with pytest.raises(ConfigError, match=r":4 \(route\[0\]\.duration_s\): .*number"):
        load_scenario(write(tmp_path, text))


def test_unit_hidden_in_value_is_refused(tmp_path):
    text = MINIMAL + "sender:\n  rate_kbps: 2 Mbit/s\n"
    with pytest.raises(ConfigError, match=r"sender\.rate_kbps"):
        load_scenario(write(tmp_path, text))


def test_negative_and_nan_are_refused(tmp_path):
    with pytest.raises(ConfigError, match=r"downlink\.queue_bytes"):
        load_scenario(write(tmp_path, MINIMAL + "downlink:\n  queue_bytes: -5\n"))
    with pytest.raises(ConfigError, match=r"uplink\.delay_ms"):
        load_scenario(write(tmp_path, MINIMAL + "uplink:\n  delay_ms: .nan\n"))


def test_missing_trace_file_names_segment(tmp_path):
    text = MINIMAL + "  - {technology: 3G, duration_s: 5, trace: nowhere.csv}\n"
    with pytest.raises(ConfigError, match=r"route\[1\]\.trace\): expected an existing file"):
        load_scenario(write(tmp_path, text))


def test_trace_path_resolves_against_scenario_folder(tmp_path):
    (tmp_path / "t.csv").write_text("time_s,rate_kbps,technology\n0,100,3G\n")
    text = MINIMAL + "  - {technology: 3G, duration_s: 5, trace: t.csv}\n"
    scenario = load_scenario(write(tmp_path, text))
    assert scenario.route[1].trace == str((tmp_path / "t.csv").resolve())


def test_unknown_policy_lists_choices(tmp_path):
    text = MINIMAL + "engine:\n  policy: magic\n"
    with pytest.raises(ConfigError, match=r"engine\.policy\): expected one of fixed, oracle"):
        load_scenario(write(tmp_path, text))


def test_missing_required_key(tmp_path):
    with pytest.raises(ConfigError, match=r"\(route\): missing required key"):
        load_scenario(write(tmp_path, "name: x\n"))


def test_yaml_syntax_error_names_line(tmp_path):
    with pytest.raises(ConfigError, match=r"s\.yaml:4: invalid YAML"):
        load_scenario(write(tmp_path, "name: x\nroute: []\nseed: 1\n  oops: 2\n"))


def test_missing_scenario_file(tmp_path):
    with pytest.raises(ConfigError, match="no such file"):
        load_scenario(tmp_path / "absent.yaml")


def test_top_level_must_be_mapping(tmp_path):
    with pytest.raises(ConfigError, match="expected a mapping"):
        load_scenario(write(tmp_path, "- 1\n- 2\n"))


def test_config_is_frozen(tmp_path):
    scenario = load_scenario(write(tmp_path, MINIMAL))
    with pytest.raises(Exception):  # noqa: B017 - pydantic's frozen error
        scenario.seed = 3


def test_shipped_scenarios_load():
    from uma.paths import scenarios_dir

    full = load_scenario(scenarios_dir() / "stockholm-uppsala-full.yaml")
    assert 2000 <= full.run_duration_s <= 3000


def test_real_trace_scenario_loads(shared_data):
    from uma.paths import scenarios_dir

    real = load_scenario(scenarios_dir() / "stockholm-uppsala-real.yaml")
    assert all(seg.trace is None or seg.trace.startswith("/") for seg in real.route)


def test_unknown_technology_names_the_segment(tmp_path):
    text = MINIMAL.replace("technology: WLAN", "technology: Carrier pigeon")
    with pytest.raises(ConfigError, match=r":3 \(route\[0\]\.technology\): expected one of GSM"):
        load_scenario(write(tmp_path, text))


from hypothesis import given, settings  # noqa: E402
from hypothesis import strategies as st  # noqa: E402

yaml_values = st.recursive(
    st.none()
    | st.booleans()
    | st.integers(-5, 5)
    | st.floats(allow_nan=True)
    | st.text(max_size=8),
    lambda children: (
        st.lists(children, max_size=3) | st.dictionaries(st.text(max_size=8), children, max_size=3)
    ),
    max_leaves=8,
)
keys = st.sampled_from(
    ["name", "seed", "route", "source", "engine", "receiver", "downlink", "bogus"]
)


@given(data=st.dictionaries(keys, yaml_values, max_size=5))
@settings(max_examples=150, deadline=None)
def test_any_yaml_mapping_is_a_scenario_or_one_config_error(tmp_path_factory, data):
    import yaml

    path = tmp_path_factory.mktemp("h") / "s.yaml"
    path.write_text(yaml.safe_dump(data))
    try:
        scenario = load_scenario(path)
    except ConfigError as err:
        assert "s.yaml" in str(err) and "\n" not in str(err)
    else:
        assert scenario.route


def test_duplicate_key_names_both_lines(tmp_path):
    text = MINIMAL + "seed: 1\nengine:\n  policy: oracle\n  safety: 0.9\n  policy: fixed\n"
    with pytest.raises(
        ConfigError, match=r"s.yaml:9 \(engine\.policy\): duplicate key, already given on line 7"
    ):
        load_scenario(write(tmp_path, text))
    with pytest.raises(ConfigError, match=r":6 \(seed\): duplicate key, already given on line 5"):
        load_scenario(write(tmp_path, MINIMAL + "seed: 1\nseed: 2\n"))


def test_trace_that_is_a_folder_is_named_as_a_folder(tmp_path):
    (tmp_path / "traces").mkdir()
    text = MINIMAL + "  - {technology: 3G, duration_s: 5, trace: traces}\n"
    with pytest.raises(ConfigError, match=r"route\[1\]\.trace\): expected a file, got a folder"):
        load_scenario(write(tmp_path, text))


def test_policy_names_are_the_engines_policies():
    from uma.config.scenario import POLICY_NAMES
    from uma.engine.policy import POLICIES

    assert set(POLICY_NAMES) == set(POLICIES)


def test_climb_names_are_the_policys_climbs_and_a_bad_one_is_named(tmp_path):
    from uma.config.engine import CLIMB_NAMES
    from uma.engine.policy import CLIMBS

    assert CLIMB_NAMES == CLIMBS
    assert load_scenario(write(tmp_path, MINIMAL)).engine.climb == "stream"
    step = load_scenario(write(tmp_path, MINIMAL + "engine: {climb: step}\n"))
    assert step.engine.climb == "step"
    with pytest.raises(ConfigError, match=r"engine\.climb.*expected one of step, stream, fit"):
        load_scenario(write(tmp_path, MINIMAL + "engine: {climb: leap}\n"))


@pytest.mark.parametrize(("key", "default"), [("drained_queue", False), ("rung_floor", True)])
def test_engine_switches_have_their_default_take_the_other_and_refuse_a_non_boolean(
    tmp_path, key, default
):
    assert getattr(load_scenario(write(tmp_path, MINIMAL)).engine, key) is default
    flipped = f"engine: {{{key}: {str(not default).lower()}}}\n"
    assert getattr(load_scenario(write(tmp_path, MINIMAL + flipped)).engine, key) is (not default)
    with pytest.raises(ConfigError, match=rf"engine\.{key}"):
        load_scenario(write(tmp_path, MINIMAL + f"engine: {{{key}: maybe}}\n"))


def test_switching_calm_is_off_by_default_and_not_negative(tmp_path):
    assert load_scenario(write(tmp_path, MINIMAL)).engine.switching.calm_ms == 0.0
    on = load_scenario(write(tmp_path, MINIMAL + "engine: {switching: {calm_ms: 2000}}\n"))
    assert on.engine.switching.calm_ms == 2000.0
    with pytest.raises(ConfigError, match=r"engine\.switching\.calm_ms"):
        load_scenario(write(tmp_path, MINIMAL + "engine: {switching: {calm_ms: -1}}\n"))


def test_engine_and_receiver_tuning_is_configurable(tmp_path):
    text = MINIMAL + (
        "engine: {stale_reports: 5, max_backlog_ms: 500, presume_lost_ms: 1000,"
        " probe_interval_ms: 250}\nreceiver: {keyframe_retry_ms: 400, base_delay_window_s: 4}\n"
    )
    scenario = load_scenario(write(tmp_path, text))
    assert scenario.engine.stale_reports == 5 and scenario.engine.probe_interval_ms == 250
    assert scenario.receiver.keyframe_retry_ms == 400
    with pytest.raises(ConfigError, match=r"engine\.stale_reports"):
        load_scenario(write(tmp_path, MINIMAL + "engine: {stale_reports: 0}\n"))


def test_model_validate_checks_names_as_loading_does():
    from pydantic import ValidationError

    from uma.config import Scenario

    base = {"name": "x", "route": [{"technology": "3G", "duration_s": 1}]}
    with pytest.raises(ValidationError, match="expected one of fixed, oracle, throughput"):
        Scenario.model_validate(base | {"engine": {"policy": "magic"}})
    with pytest.raises(ValidationError, match="policy 'fixed' needs 'fixed_rung'"):
        Scenario.model_validate(base | {"engine": {"policy": "fixed"}})
    with pytest.raises(ValidationError, match="full-frame codec"):
        Scenario.model_validate(base | {"engine": {"codec": "mbc"}})


def test_switching_and_estimator_names_are_the_engines():
    from uma.config.scenario import ESTIMATOR_KINDS, SWITCHING_NAMES
    from uma.engine.policy import SWITCHING
    from uma.engine.rate import RATE_CONTROLS

    assert set(SWITCHING_NAMES) == set(SWITCHING) and "oracle" in SWITCHING_NAMES
    assert set(ESTIMATOR_KINDS) == set(RATE_CONTROLS)
