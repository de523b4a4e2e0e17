"""docs/targets.md: every verdict computed from its record (scripts/readme_targets.py).

The first test checks the repository's page; the others show that a verdict turns when a
figure crosses its target, and that a record that is not what a target names is refused.
"""

import copy
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).parents[1]
sys.path.insert(0, str(ROOT / "scripts"))

import readme_tables  # noqa: E402
import readme_targets  # noqa: E402

RESULTS = ROOT / "docs" / "results"


def test_targets_md_is_what_its_records_render():
    problem = readme_tables.check(ROOT / "docs" / "targets.md", RESULTS, True, "results")
    assert problem is None, f"{problem}\n(run: python scripts/readme_tables.py write)"


def _cell(psnr, ssim, frozen=0.05):
    return {"psnr_face_db": psnr, "ssim_face": ssim, "freeze_ratio": frozen}


def _headline(p95_ms=990.0, gprs_psnr=26.0, gsm_psnr=22.0):
    uma = {
        "freeze_ratio": 0.05, "delay_p95_ms": p95_ms, "switch_lag_s": 0.5,
        "by_technology": {"3G": _cell(33, 0.9), "GPRS": _cell(gprs_psnr, 0.88),
                          "GSM": _cell(gsm_psnr, 0.9)},
    }  # fmt: skip
    h264 = {
        "freeze_ratio": 0.2, "delay_p95_ms": 1500.0, "switch_lag_s": None,
        "by_technology": {"3G": _cell(33, 0.9), "GPRS": _cell(25.9, 0.71),
                          "GSM": _cell(24.6, 0.67)},
    }  # fmt: skip
    return {"scenarios": {"stockholm-uppsala": {"uma": uma, "h264": h264}}}


def _verdicts(table: str) -> dict[str, str]:
    rows = [line.split(" | ") for line in table.splitlines()[2:]]
    return {row[0].strip("| "): row[-1].strip("| ") for row in rows}


def test_the_commute_verdicts_turn_at_their_targets():
    met = _verdicts(readme_targets.commute_targets([_headline(p95_ms=1000.0)], {}))
    assert met["delay p95 <= 1,000 ms"] == "met"
    assert met["GPRS face PSNR at least H.264 only's"] == "met"
    missed = _verdicts(readme_targets.commute_targets([_headline(1000.5, 25.8)], {}))
    assert missed["delay p95 <= 1,000 ms"] == "**not met**"
    assert missed["GPRS face PSNR at least H.264 only's"] == "**not met**"


def test_the_low_technology_face_rule_needs_psnr_and_the_ssim_margin():
    faces = _verdicts(readme_targets.commute_targets([_headline()], {"faces": "27"}))
    gprs, gsm = (next(v for k, v in faces.items() if k.startswith(t)) for t in ("GPRS", "GSM"))
    assert (gprs, gsm) == ("met", "**not met**")  # GSM: 22.0 dB against 24.6
    result = _headline(gsm_psnr=24.6)
    result["scenarios"]["stockholm-uppsala"]["uma"]["by_technology"]["GSM"]["ssim_face"] = 0.76
    faces = _verdicts(readme_targets.commute_targets([result], {"faces": "27"}))
    assert next(v for k, v in faces.items() if k.startswith("GSM")) == "**not met**"  # 0.76 < 0.77


def test_the_real_commute_needs_a_label_for_every_seed_and_reads_the_bound():
    record = copy.deepcopy(_headline(p95_ms=1400.0))
    bound = {"scenarios": {"stockholm-uppsala": {"packets": {"40": {"delay_p95_ms": 1551.0}}}}}
    table = readme_targets.real_targets([record, bound], {"seeds": "1", "bound": "1"})
    assert "| seed 1: delay p95 <= 1,500 ms | 1,400 ms | met |" in table
    assert "delay p95 of 1,551 ms" in table
    with pytest.raises(ValueError, match="2 labels"):
        readme_targets.real_targets([record], {"seeds": "1,2"})


def _trace(uma_p95, gcc_p95=1000.0, oracle_p95=500.0, uma_ssim=12.0, gcc_ssim=12.0):
    def engine(p95, ssim):
        return {"delay_p95_ms": p95, "ssim_db_unfrozen": ssim}

    return {"engines": {"uma": engine(uma_p95, uma_ssim), "gcc": engine(gcc_p95, gcc_ssim),
                        "oracle": engine(oracle_p95, 13.0)}}  # fmt: skip


def test_the_links_rules_hold_on_every_trace_or_name_the_ones_that_miss():
    good = {"traces": {"a": _trace(900.0), "b": _trace(1000.0, uma_ssim=11.5)}}
    assert "**not met**" not in readme_targets.links_targets([good], {"sets": "x"})
    bad = {"traces": {"a": _trace(900.0), "b": _trace(1001.0, uma_ssim=11.49)}}
    table = readme_targets.links_targets([bad], {"sets": "x"})
    assert "| x: uma's p95 at most GCC's, on every trace | 1 of 2 (not: b) | **not met** |" in table
    # 1,001 ms is past max(1,000, 1.5 x 500) too, and 11.49 dB is more than 0.5 under 12.
    assert table.count("**not met**") == 3


def test_the_speed_target_refuses_a_headline_that_is_not_the_whole_bench():
    speed = {"runs": [{"clips": {"a": {"model_path_ms": 9.9, "kind": "real clip"}}}]}
    mbc = {"clips": {"a": {"size": "352x288"}}}
    sim = {"scenario": "s", "codecs": ["h264"], "frames": 3000, "realtime_x": 8.0}
    records = [{"result": r} for r in (speed, mbc, sim)]
    whole = {"command": "uma bench headline --workers 2 --json", "duration_s": 479.0}
    table = readme_targets.speed_targets(records + [whole], {})
    assert table.count("| met |") == 3
    part = dict(whole, command="uma bench headline --workers 2 --skip-real --json")
    with pytest.raises(ValueError, match="not the whole"):
        readme_targets.speed_targets(records + [part], {})


def test_the_salsify_targets_say_what_the_oracle_reached_when_it_ran():
    def row(p95, ssim, frozen):
        return {"delay_p95_ms": p95, "ssim_db_unfrozen": ssim, "freeze_ratio": frozen}

    result = {"estimators": {"uma": row(2999.0, 13.2, 0.12), "gcc": row(4000.0, 11.0, 0.12)},
              "published": {"salsify_1c": {"ssim_db": 13.2}}}  # fmt: skip
    table = readme_targets.salsify_targets([result], {})
    assert "oracle" not in table and table.count("| met |") == 3
    result["estimators"]["oracle"] = row(2074.0, 11.68, 0.1143)
    table = readme_targets.salsify_targets([result], {})
    assert table.startswith("The oracle policy") and "unfrozen SSIM 11.68 dB" in table
