"""The renderers of the README's and measured.md's generated blocks, on hand-made records:
issue 26's links rules, issue 27's low-technology face target, the seed tables, the speed
table, and scripts/model_path_runs.py's record."""

from __future__ import annotations

import json
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).parents[1]
sys.path.insert(0, str(ROOT / "scripts"))

import record_bench  # noqa: E402

COMMIT = "0123456789abcdef0123456789abcdef01234567"


def _links_trace(uma_p95: float, gcc_p95: float, oracle_p95: float, uma_ssim: float) -> dict:
    def engine(p95: float, ssim: float) -> dict:
        return {"delay_p95_ms": p95, "ssim_db_unfrozen": ssim, "freeze_ratio": 0.1}

    return {
        "engines": {
            "uma": engine(uma_p95, uma_ssim),
            "gcc": engine(gcc_p95, 12.0),
            "oracle": engine(oracle_p95, 13.0),
        }
    }


def test_the_links_rules_are_issue_26s_three_per_trace():
    import readme_blocks

    result = {
        "traces": {
            "calm": _links_trace(400, 500, 300, 11.6),  # all three met (1,000 ms floor)
            "slow": _links_trace(1_600, 1_500, 1_100, 11.4),  # above gcc, within 1.5 x oracle
            "harsh": _links_trace(2_000, 3_000, 1_200, 12.5),  # above 1.5 x oracle (1,800)
        }
    }
    rows = readme_blocks.links_table([result], {}).splitlines()[2:]
    assert [row.split(" | ")[-3:] for row in rows] == [
        ["yes", "yes", "yes |"],
        ["**no**", "yes", "**no** |"],
        ["yes", "**no**", "yes |"],
    ]
    said = readme_blocks.links_verdicts([result], {})
    assert said == (
        "uma's p95 at most GCC's on 2 of 3; p95 within max(1,000 ms, 1.5 x the oracle's) on 2 "
        "of 3; unfrozen SSIM at most 0.5 dB below GCC's on 2 of 3"
    )


def _low_row(gprs: tuple[float, float], gsm: tuple[float, float]) -> dict:
    techs = {"GPRS": gprs, "GSM": gsm}
    return {
        "by_technology": {
            tech: {"psnr_face_db": psnr, "ssim_face": ssim} for tech, (psnr, ssim) in techs.items()
        }
    }


def test_the_low_targets_ask_issue_27s_ssim_margin_of_a_tenth():
    import readme_blocks

    rows = {
        "h264": _low_row((25.0, 0.70), (24.0, 0.60)),
        "uma": _low_row((25.0, 0.80), (24.1, 0.68)),  # GPRS +0.10 met; GSM +0.08 is not
        "predictive": _low_row((24.9, 0.90), (24.0, 0.75)),  # GPRS PSNR short; GSM met
    }
    record = {"scenarios": {"commute": rows}}
    table = readme_blocks.headline_low_targets([record], {}).splitlines()
    assert table[2] == "| uma (threshold switching) | +0.0 dB, +0.100 | +0.1 dB, +0.080 | GPRS |"
    assert table[3].endswith("| GSM |")
    wider = readme_blocks.headline_low_targets([record], {"ssim_margin": "0.05"}).splitlines()
    assert wider[2].endswith("| GPRS and GSM |")


def test_the_seeds_face_table_judges_each_seed_and_counts_each_technology():
    import readme_blocks

    seeds = [
        {"uma": _low_row((22.4, 0.67), (22.6, 0.68)), "h264": _low_row((21.9, 0.55), (21.9, 0.55))},
        {"uma": _low_row((21.9, 0.65), (21.9, 0.65)), "h264": _low_row((22.2, 0.57), (21.7, 0.54))},
    ]
    records = [{"scenarios": {"real": rows}} for rows in seeds]
    text = readme_blocks.RENDERERS["headline-seeds-faces"](records, {"seeds": "1,2"}).splitlines()
    assert (
        text[2]
        == "| 1 | 22.40 / 0.670 | 21.90 / 0.550 | 22.60 / 0.680 | 21.90 / 0.550 | GPRS and GSM |"
    )
    assert text[3].endswith("| GSM |")  # GPRS: PSNR 0.3 dB short
    assert text[-1] == (
        "Face PSNR at least h264's and face SSIM at least 0.1 above it: GPRS on 1 of 2, GSM on 2 of 2."
    )


def _seed_record(uma_p95: float, uma_frozen: float, h264_p95: float) -> dict:
    row = {"delay_p95_ms": uma_p95, "freeze_ratio": uma_frozen}
    base = {"delay_p95_ms": h264_p95, "freeze_ratio": 0.5}
    return {"scenarios": {"real": {"uma": row, "h264": base}}}


def test_the_seeds_table_and_verdict_count_each_seed_and_take_medians():
    import readme_blocks

    results = [
        _seed_record(5_000, 0.20, 6_000),  # below H.264's p95
        _seed_record(5_500, 0.14, 5_200),  # above it; frozen within 0.15
        _seed_record(4_000, 0.30, 4_500),
    ]
    args = {"seeds": "1,2,3"}
    table = readme_blocks.headline_seeds(results, args).splitlines()
    assert table[2] == "| 1 | 5,000 | 6,000 | 0.200 | 0.500 |"
    assert table[-1] == "| median | 5,000 | 5,200 | 0.200 | 0.500 |"
    assert readme_blocks.headline_seeds_verdict(results, args) == (
        "over seeds 1,2,3, uma's p95 is below H.264 only's on 2 of 3 (medians 5,000 against "
        "5,200 ms) and its frozen share at most 0.15 on 1 of 3 (median 0.200)"
    )
    with pytest.raises(ValueError, match="3 records, 2 labels"):
        readme_blocks.headline_seeds(results, {"seeds": "1,2"})


def _speed_run(load: float, walls: dict[str, float]) -> dict:
    kinds = {"talking-head": "model's own rendering"}
    return {
        "load_1m": {"before": load, "after": load},
        "clips": {
            name: {
                "kind": kinds.get(name, "real clip"),
                "model_path_ms": wall,
                "model_path_cpu_ms": wall - 0.5,
            }  # fmt: skip
            for name, wall in walls.items()
        },
    }


def test_the_speed_table_takes_each_clips_median_over_runs_and_judges_real_clips_only():
    import readme_blocks

    runs = [
        _speed_run(1.0, {"talking-head": 9.0, "akiyo": 12.0, "foreman": 5.0}),
        _speed_run(1.2, {"talking-head": 8.0, "akiyo": 9.5, "foreman": 11.0}),
        _speed_run(1.1, {"talking-head": 9.5, "akiyo": 10.5, "foreman": 6.0}),
    ]
    text = readme_blocks.mbc_speed_table([{"runs": runs}], {}).splitlines()
    assert text[2] == "| talking head (model's own rendering) | 9.0 | 8.0 | 9.5 | **9.0** | 8.5 |"
    assert text[3] == "| akiyo | 12.0 | 9.5 | 10.5 | **10.5** | 10.0 |"
    assert text[-1] == (
        "Load (1 min) before each run: 1.00, 1.20, 1.10. The median is within 10 ms on 1 of 2 "
        "real clips; talking head: 9.0 ms; akiyo: 10.5 ms."
    )
    assert "on 2 of 2 real clips" in readme_blocks.mbc_speed_table(
        [{"runs": runs}], {"limit": "11"}
    )


def test_the_speed_runs_compare_every_figure_but_times_and_loads():
    import model_path_runs

    result = {"clips": {"akiyo": {"kind": "real clip", "params_kbps": 2.9, "payload_bytes": 3,
                                  "model_path_ms": 9.1, "stages_cpu_ms": {"track": 1.0},
                                  "kernel_warm_up_s": 0.2, "load_1m": 1.0, "reinits": 1}}}  # fmt: skip
    kept = model_path_runs.figures(result)
    assert kept == {"clips": {"akiyo": {"kind": "real clip", "params_kbps": 2.9,
                                        "payload_bytes": 3, "reinits": 1}}}  # fmt: skip
    other = json.loads(json.dumps(result))
    other["clips"]["akiyo"]["model_path_ms"] = 14.0
    assert model_path_runs.figures(other) == kept
    other["clips"]["akiyo"]["reinits"] = 2
    assert model_path_runs.figures(other) != kept


def _speed_bench(reinits: int, wall_ms: float) -> dict:
    clip = {"kind": "real clip", "reinits": reinits, "model_path_ms": wall_ms,
            "model_path_cpu_ms": wall_ms, "stages_ms": {}, "stages_cpu_ms": {}}  # fmt: skip
    return {"clips": {"akiyo": clip}}


def test_the_speed_runs_are_recorded_only_when_every_run_gives_the_same_figures(
    monkeypatch, tmp_path
):
    import model_path_runs

    out = tmp_path / "mbc-speed.json"
    answers = {"rev-parse": COMMIT, "status": ""}
    monkeypatch.setattr(record_bench, "_git", lambda *args: answers[args[0]])
    monkeypatch.setattr(record_bench, "_machine", lambda: {"class": "default"})
    monkeypatch.setattr(record_bench, "result_path", lambda name, variant: out)
    load = {"before": 1.0, "after": 1.0}
    runs = iter([_speed_bench(1, 9.0), _speed_bench(1, 11.0)])
    monkeypatch.setattr(model_path_runs, "_run_once", lambda argv: (next(runs), load))
    assert model_path_runs.record(2) == out
    doc = json.loads(out.read_text(encoding="utf-8"))
    assert doc["command"].startswith("uma bench mbc --json") and doc["commit"] == COMMIT
    walls = [run["clips"]["akiyo"]["model_path_ms"] for run in doc["result"]["runs"]]
    assert walls == [9.0, 11.0]
    out.unlink()
    runs = iter([_speed_bench(1, 9.0), _speed_bench(2, 9.0)])  # run 2 re-initialised more
    with pytest.raises(RuntimeError, match="run 2: its figures differ"):
        model_path_runs.record(2)
    assert not out.exists()
    answers["status"] = " M uma/mbc/layers.py"
    with pytest.raises(record_bench.RecordError, match="uncommitted changes"):
        model_path_runs.record(2)
