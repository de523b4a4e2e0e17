"""The benchmarks run and print the keys docs/benchmarks.md requires (tiny sizes; no timing asserted)."""

import json

import pytest

from uma.cli import main


def test_bench_codec_reports_every_rung(capsys):
    from uma.video import load_ladder

    assert (
        main(["bench", "codec", "--frames", "30", "--video", __file__, "--json"]) == 2
    )  # not a video
    capsys.readouterr()
    from uma.bench.codec import run_codec_bench

    result = run_codec_bench(video=None, frames=30)
    assert len(result["rungs"]) == len(load_ladder().rungs)
    assert all(-50 < rung["error_pct"] < 50 for rung in result["rungs"])


def test_bench_sim_json_keys(capsys):
    assert main(["bench", "sim", "--frames", "25", "--size", "qcif", "--json"]) == 0
    result = json.loads(capsys.readouterr().out)
    for key in ("frames", "video", "sim_s", "codec_s", "metrics_s", "ratio", "realtime_x"):
        assert key in result
    assert result["frames"] == 25 and result["video"] == "176x144@25"


def test_bench_init_json_keys(capsys):
    assert (
        main(
            [
                "bench",
                "init",
                "--cases",
                "2",
                "--cif-frames",
                "0",
                "--json",
                "--faces",
                "/nonexistent",
            ]
        )
        == 2
    )
    capsys.readouterr()
    from pathlib import Path

    from uma.bench.init import InitBenchConfig, run_init_bench

    result = run_init_bench(
        InitBenchConfig(cases=2, faces=Path("/nonexistent"), yale=None, cif_frames=0)
    )
    assert result["cases"] == 2 and result["image"] == "92x112"
    for method in ("saabs", "saabs_ic", "gauss_newton", "dual_annealing", "hybrid"):
        stats = result["methods"][method]
        for key in (
            "mde_median_px",
            "mde_p95_px",
            "success_rate",
            "time_median_ms",
            "evaluations_median",
        ):
            assert key in stats and key in stats["large_pose"]


@pytest.mark.slow  # one and two worker processes over twelve points: about 8 s
def test_bench_sweep_json_keys(capsys, tmp_path):
    scenario = tmp_path / "s.yaml"
    scenario.write_text(
        "name: s\nsource: {kind: pattern, width: 64, height: 48}\n"
        "route:\n  - {technology: 3G, duration_s: 5}\n"
    )
    args = ["bench", "sweep", "--scenario", str(scenario), "--seconds", "0.4", "--json"]
    assert main(args) == 0
    result = json.loads(capsys.readouterr().out)
    assert result["points"] == 12 and result["identical"] is True
    # t1_s and t2_s are rounded to 1 ms, the speed-up is taken before rounding them
    assert result["speedup"] == pytest.approx(result["t1_s"] / result["t2_s"], rel=5e-3)


def test_bench_salsify_json_keys(capsys, shared_data):
    import pytest

    pytest.importorskip("aiortc")
    # One second (each frame's face search dominates the run): every key is filled by then.
    argv = ["bench", "salsify", "--frames", "25", "--clip-frames", "5", "--skip-default", "--json"]
    assert main(argv) == 0
    result = json.loads(capsys.readouterr().out)
    assert result["trace"].endswith("TMobile-UMTS-driving.down") and result["frames"] == 25
    for name in ("uma", "webrtc"):
        row = result["estimators"][name]
        for key in ("delay_p95_ms", "ssim_db", "freeze_ratio", "kbps_h264"):
            assert row[key] is not None, (name, key)
    assert result["scenario"] == "salsify-tmobile-umts"
    assert set(result["published"]) == {"salsify_1c", "webrtc", "skype", "facetime"}
    for row in result["published"].values():
        assert set(row) == {"delay_p95_ms", "ssim_db"}
    assert result["published"]["salsify_1c"] == {"delay_p95_ms": 3907.0, "ssim_db": 13.2}
    assert result["estimators"]["webrtc"]["kbps_padding"] >= 0


def test_bench_salsify_oracle_is_the_oracle_policy_not_an_estimator():
    from uma.bench.salsify import KINDS, ORACLE, _with_estimator
    from uma.config import load_scenario

    scenario = load_scenario(None)
    oracle = _with_estimator(scenario, ORACLE)
    assert oracle.engine.policy == "oracle" and ORACLE in KINDS
    assert oracle.engine.estimator == scenario.engine.estimator
    gcc = _with_estimator(scenario, "gcc")
    assert gcc.engine.policy == scenario.engine.policy and gcc.engine.estimator.kind == "gcc"


def test_bench_salsify_refuses_an_unknown_kind_naming_the_choices(capsys, shared_data):
    assert main(["bench", "salsify", "--estimators", "uma,gcc,psychic", "--frames", "1"]) == 2
    err = capsys.readouterr().err
    assert "--estimators" in err and "oracle" in err and "psychic" in err
