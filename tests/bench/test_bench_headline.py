"""`uma bench headline`: the engines it compares and the keys it prints (a short route)."""

import contextlib
import io
import json

import pytest

from uma.bench.headline import ENGINES, engine_scenario
from uma.cli import main
from uma.config import load_scenario
from uma.paths import scenarios_dir


def test_each_engine_changes_only_what_it_names():
    base = load_scenario(scenarios_dir() / "stockholm-uppsala.yaml")
    h264, uma, predictive_, oracle, av1, av1_mbc = (
        engine_scenario(base, engine) for engine in ENGINES
    )
    assert av1.engine.codec == av1_mbc.engine.codec == "av1"
    assert av1.engine.switching.policy == "none"
    assert av1_mbc.engine.switching.policy == "threshold" and av1_mbc.engine.policy == "throughput"
    assert h264.engine.codec == uma.engine.codec == oracle.engine.codec == base.engine.codec
    assert predictive_.engine.switching.policy == "predictive"
    assert h264.engine.switching.policy == "none" and h264.engine.policy == "throughput"
    assert uma.engine.switching.policy == "threshold" and uma.engine.policy == "throughput"
    assert oracle.engine.switching.policy == "oracle" and oracle.engine.policy == "oracle"
    assert {s.receiver.playout for s in (h264, uma, oracle)} == {"adaptive"}
    assert all(s.route == base.route and s.source == base.source for s in (h264, uma, oracle))
    fixed = engine_scenario(base, "uma", playout="fixed")
    assert fixed.receiver == base.receiver
    predictive = base.model_copy(
        update={
            "engine": base.engine.model_copy(
                update={
                    "switching": base.engine.switching.model_copy(update={"policy": "predictive"})
                }
            )
        }
    )
    assert engine_scenario(predictive, "uma").engine.switching.policy == "predictive"
    with pytest.raises(ValueError, match="engine"):
        engine_scenario(base, "vp8")


# 1.4 s, WLAN into GSM: every engine runs, the switching ones initialise MBC (35 frames: the
# six runs' fixed costs, opening the talking head and fitting the face, are most of the time).
MICRO = """\
name: micro-gsm
seed: 1
source: {kind: talking-head, width: 176, height: 144, fps: 25}
route:
  - {technology: WLAN, duration_s: 0.4}
  - {technology: GSM, duration_s: 1.0}
engine:
  policy: oracle
  switching: {policy: threshold, to_mbc_below_kbps: 30, to_h264_above_kbps: 60, min_dwell_ms: 200}
receiver: {playout_delay_ms: 800}
"""


def _headline(*args: str) -> tuple[int, str]:
    out = io.StringIO()
    with contextlib.redirect_stdout(out):
        code = main(["bench", "headline", *args, "--quiet"])
    return code, out.getvalue()


@pytest.fixture(scope="module")
def micro(tmp_path_factory):
    """The micro scenario's file and its serial headline (JSON and table), shared by the tests."""
    path = tmp_path_factory.mktemp("headline") / "micro.yaml"
    path.write_text(MICRO)
    code, out = _headline("--scenario", str(path), "--json")
    assert code == 0
    return path, json.loads(out)


def test_headline_json_keys_on_a_micro_route(micro):
    rows = micro[1]["scenarios"]["micro-gsm"]
    assert list(rows) == list(ENGINES)
    for row in rows.values():
        assert set(row) >= {"freeze_ratio", "ssim_face", "switches", "inits", "by_technology"}
        assert "GSM" in row["by_technology"] and set(row["by_technology"]) <= {"WLAN", "GSM"}
        for cell in row["by_technology"].values():
            assert set(cell) == {"freeze_ratio", "psnr_face_db", "ssim_face"}
    assert rows["h264"]["kbps_mbc"] == 0 and rows["h264"]["inits"] == 0
    assert rows["uma"]["inits"] >= 1 and rows["uma"]["kbps_mbc"] > 0
    assert rows["uma"]["init_mde_px"] is not None and rows["uma"]["init_mde_px"] < 5.0
    assert rows["uma"]["freeze_ratio"] < rows["h264"]["freeze_ratio"]
    assert rows["oracle"]["switches"] >= 1
    assert rows["av1"]["codec"] == "av1" and rows["av1"]["kbps_video"] > 0
    assert rows["av1"]["kbps_h264"] == 0 and rows["av1"]["kbps_mbc"] == 0
    assert rows["av1+mbc"]["inits"] >= 1 and rows["av1+mbc"]["kbps_mbc"] > 0
    assert rows["h264"]["switch_lag_s"] is None
    assert rows["uma"]["switch_lag_s"] is not None and 0 <= rows["uma"]["switch_lag_s"] < 1.0


# One second of the pattern: no face, so no MBC; the cheapest run that still has every engine.
PATTERN = """\
name: micro-pattern
seed: 1
source: {kind: pattern, width: 128, height: 96, fps: 25}
route:
  - {technology: WLAN, duration_s: 0.5}
  - {technology: GSM, duration_s: 0.5}
"""


def _same_tables(path, serial: dict) -> None:
    from uma.bench.headline import format_table

    code, out = _headline("--scenario", str(path), "--json", "--workers", "2")
    assert code == 0
    parallel = json.loads(out)

    def without_wall_clock(result):
        for rows in result["scenarios"].values():
            for row in rows.values():
                assert row.pop("wall_s") >= 0
        return result

    assert without_wall_clock(parallel) == without_wall_clock(serial)
    assert format_table(parallel) == format_table(serial)


def test_headline_on_two_workers_gives_the_serial_tables(tmp_path):
    path = tmp_path / "pattern.yaml"
    path.write_text(PATTERN)
    code, out = _headline("--scenario", str(path), "--json")
    assert code == 0
    serial = json.loads(out)
    assert list(serial["scenarios"]["micro-pattern"]) == list(ENGINES)
    _same_tables(path, serial)


@pytest.mark.slow
def test_headline_on_two_workers_gives_the_serial_tables_with_mbc(micro):
    _same_tables(*micro)


@pytest.mark.parametrize(
    "args, expected",
    [
        (["--workers", "0"], "--workers"),
        (["--workers", "2", "--scheduler", "tcp://127.0.0.1:1"], "--workers and --scheduler"),
        (["--timeout", "0"], "--timeout"),
    ],
)
def test_headline_refuses_bad_parallel_options(capsys, args, expected):
    assert main(["bench", "headline", *args]) == 2
    assert expected in capsys.readouterr().err


@pytest.mark.slow
def test_headline_json_keys_on_a_short_route(capsys):
    scenario = str(scenarios_dir() / "wlan-gsm-wlan.yaml")
    assert main(["bench", "headline", "--scenario", scenario, "--json"]) == 0
    result = json.loads(capsys.readouterr().out)
    rows = result["scenarios"]["wlan-gsm-wlan"]
    assert set(rows) == set(ENGINES)
    keys = [
        "freeze_ratio",
        "displayed_fps",
        "psnr_db",
        "ssim",
        "psnr_face_db",
        "ssim_face",
        "delay_p95_ms",
        "kbps_h264",
        "kbps_mbc",
        "switches",
        "inits",
        "init_mde_px",
        "description_delivered_s",
        "by_technology",
    ]
    for row in rows.values():
        assert all(key in row for key in keys)
        for cell in row["by_technology"].values():
            assert set(cell) == {"freeze_ratio", "psnr_face_db", "ssim_face"}
    assert rows["h264"]["kbps_mbc"] == 0 and rows["h264"]["inits"] == 0
    assert rows["uma"]["inits"] >= 1 and rows["uma"]["kbps_mbc"] > 0
    # The talking head has ground truth: the initialisations' error is measured.
    assert rows["uma"]["init_mde_px"] is not None and rows["uma"]["init_mde_px"] < 5.0
    assert rows["oracle"]["switches"] >= 2


def test_headline_refuses_a_bad_duration(capsys):
    assert main(["bench", "headline", "--duration-s", "-1"]) == 2
    assert "--duration-s" in capsys.readouterr().err


def test_targets_judge_both_ways_and_say_none_without_a_value():
    from uma.bench.headline import _targets

    def row(frozen, face_db, gsm_ssim=None):
        by_technology = {} if gsm_ssim is None else {"GSM": {"ssim_face": gsm_ssim}}
        return {"freeze_ratio": frozen, "psnr_face_db": face_db, "by_technology": by_technology}

    met = _targets({"h264": row(0.4, 20.0, 0.4), "uma": row(0.05, 21.0, 0.5)}, real=False)
    assert met["freeze_ratio_share_of_h264"] == 0.125 and met["freeze_ratio_at_most_20_percent"]
    assert met["low_ssim_face_above_h264"]
    missed = _targets({"h264": row(0.4, 20.0, 0.5), "uma": row(0.2, 21.0, 0.4)}, real=False)
    assert missed["freeze_ratio_at_most_20_percent"] is False
    assert missed["low_ssim_face_above_h264"] is False
    real = _targets({"h264": row(0.5, None), "uma": row(0.6, 20.0)}, real=True)
    assert real == {"freeze_ratio_lower": False, "psnr_face_db_at_least_h264": None}
