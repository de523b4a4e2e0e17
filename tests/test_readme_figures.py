"""README.md's measured figures are what docs/results/ records render (scripts/readme_tables.py).

The first tests check the repository itself; the others show that the check fails on a
tampered figure, a missing or incomplete record, and a table typed in by hand.
"""

import json
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).parents[1]
sys.path.insert(0, str(ROOT / "scripts"))

import readme_tables  # noqa: E402
import record_bench  # noqa: E402

RESULTS = ROOT / "docs" / "results"
COMMIT = "0123456789abcdef0123456789abcdef01234567"


def test_the_readme_is_what_its_records_render():
    problem = readme_tables.check(ROOT / "README.md", RESULTS)
    assert problem is None, f"{problem}\n(run: python scripts/readme_tables.py write)"


def test_measured_md_is_what_its_records_render_and_lists_every_record():
    document = ROOT / "docs" / "measured.md"
    problem = readme_tables.check(document, RESULTS, strict=False, results_link="results")
    assert problem is None, f"{problem}\n(run: python scripts/readme_tables.py write)"
    text = document.read_text(encoding="utf-8")
    assert "<!-- fig records -->" in text
    for path in RESULTS.glob("*.json"):
        assert f"[`{path.name}`](results/{path.name})" in text


def test_the_readme_quotes_every_bench_it_names_through_blocks():
    text = (ROOT / "README.md").read_text(encoding="utf-8")
    named = {match["spec"].split()[0] for match in readme_tables._BLOCK.finditer(text)}
    assert {
        "headline-table",
        "headline-low-targets",
        "mbc-table",
        "sim-table",
        "value",
        "source",
    } <= named


def test_every_record_names_its_command_and_a_clean_commit_in_history():
    records = sorted(RESULTS.glob("*.json"))
    assert records, "docs/results/ holds no records"
    for path in records:
        record = readme_tables.load_record(RESULTS, path.name, "test")
        assert record.command.startswith("uma bench ") and "--json" in record.command
        assert record.raw["dirty"] is False
        if (ROOT / ".git").exists():  # a clone: the commit named must be in its history
            found = subprocess.run(
                ["git", "merge-base", "--is-ancestor", record.commit, "HEAD"],
                cwd=ROOT,
                check=False,
                capture_output=True,
            )
            assert found.returncode == 0, f"{path.name}: {record.commit} is not in HEAD's history"


def _record(result, **extra):
    return (
        {"command": "uma bench toy --json", "commit": COMMIT, "dirty": False}
        | {"result": result}
        | extra
    )


TOY = """# toy
The rate is <!-- fig value toy.json rate_kbps .1f -->12.3<!-- /fig --> kbit/s (<!-- fig source toy.json -->`uma bench toy --json` on `0123456` ([record](docs/results/toy.json))<!-- /fig -->).

<!-- fig salsify-table toy.json -->
| Salsify scenario | delay p95 ms | SSIM dB | SSIM dB unfrozen | frozen | video kbit/s (+ padding) |
|---|---|---|---|---|---|
| uma H.264, uma's controller | 3,116 | 10.51 | 12.30 | 0.154 | 697 |
| Salsify-1c (published) | 3,907 | 13.2 | | | |

From `uma bench toy --json` on `0123456` ([record](docs/results/toy.json)).
<!-- /fig -->
"""
TOY_RESULT = {
    "rate_kbps": 12.34,
    "estimators": {
        "uma": {
            "delay_p95_ms": 3116.0,
            "ssim_db": 10.514,
            "ssim_db_unfrozen": 12.3,
            "freeze_ratio": 0.1544,
            "kbps_h264": 697.2,
            "kbps_padding": None,
        }
    },
    "published": {"salsify_1c": {"delay_p95_ms": 3907, "ssim_db": 13.2}},
}


@pytest.fixture
def toy(tmp_path):
    """A README and its one record that agree."""
    (tmp_path / "results").mkdir()
    (tmp_path / "results" / "toy.json").write_text(json.dumps(_record(TOY_RESULT)))
    (tmp_path / "README.md").write_text(TOY)
    return tmp_path


def test_the_toy_readme_agrees_with_its_record(toy):
    assert readme_tables.check(toy / "README.md", toy / "results") is None


def test_a_tampered_table_figure_fails_naming_its_line(toy):
    readme = toy / "README.md"
    readme.write_text(TOY.replace("| 0.154 |", "| 0.150 |"))
    problem = readme_tables.check(readme, toy / "results")
    assert problem is not None and problem.startswith("README.md:7:"), problem


def test_a_tampered_inline_figure_fails(toy):
    readme = toy / "README.md"
    readme.write_text(TOY.replace(">12.3<", ">12.4<"))
    assert readme_tables.check(readme, toy / "results").startswith("README.md:2:")


def test_a_changed_record_fails(toy):
    changed = json.loads(json.dumps(TOY_RESULT))
    changed["estimators"]["uma"]["delay_p95_ms"] = 2000.0
    (toy / "results" / "toy.json").write_text(json.dumps(_record(changed)))
    assert "2,000" in readme_tables.check(toy / "README.md", toy / "results")


def test_a_block_naming_a_missing_record_fails(toy):
    readme = toy / "README.md"
    readme.write_text(TOY.replace("fig salsify-table toy.json", "fig salsify-table gone.json"))
    problem = readme_tables.check(readme, toy / "results")
    assert "README.md:4: names docs/results/gone.json, which does not exist" in problem


@pytest.mark.parametrize(
    "damage, said",
    [
        ({"commit": None}, "expected `commit`"),
        ({"command": "make it up"}, "expected `command`"),
        ({"dirty": True}, "dirty tree"),
    ],
)
def test_an_incomplete_record_fails(toy, damage, said):
    (toy / "results" / "toy.json").write_text(json.dumps(_record(TOY_RESULT) | damage))
    assert said in readme_tables.check(toy / "README.md", toy / "results")


def test_a_table_typed_in_by_hand_outside_any_block_fails(toy):
    readme = toy / "README.md"
    readme.write_text(TOY + "\n| engine | frozen |\n|---|---|\n| uma | 0.159 |\n")
    assert "a table row with figures outside any figures block" in readme_tables.check(
        readme, toy / "results"
    )


def test_write_fills_the_blocks(toy, monkeypatch):
    readme = toy / "README.md"
    readme.write_text(TOY.replace(">12.3<", ">?<").replace("| 0.154 |", "| ? |"))
    monkeypatch.setattr(readme_tables, "ROOT", toy)
    monkeypatch.setattr(readme_tables, "RESULTS", "results")
    documents = (("README.md", True, "docs/results"), ("measured.md", False, "results"))
    monkeypatch.setattr(readme_tables, "DOCUMENTS", documents)
    (toy / "measured.md").write_text("<!-- fig records -->\n| ? |\n<!-- /fig -->\n| 0.5 |\n")
    assert readme_tables.main(["write"]) == 0
    assert readme_tables.main(["check"]) == 0
    assert "(results/toy.json) | `uma bench toy --json`" in (toy / "measured.md").read_text()


def test_the_repository_readme_fails_when_a_figure_is_tampered(tmp_path):
    if not RESULTS.is_dir():
        pytest.skip("no records yet")
    text = (ROOT / "README.md").read_text(encoding="utf-8")
    marker = "<!-- fig headline-table headline.json scenario=stockholm-uppsala -->\n| engine"
    start = text.index(marker)
    row = text.index("| uma (threshold switching) | ", start)
    cell = text.index(" | ", row + 4) + 3  # the uma row's frozen share
    tampered = text[:cell] + ("1" if text[cell] != "1" else "2") + text[cell + 1 :]
    (tmp_path / "README.md").write_text(tampered, encoding="utf-8")
    problem = readme_tables.check(tmp_path / "README.md", RESULTS)
    assert problem is not None and "uma (threshold switching)" in problem


def test_record_bench_refuses_a_dirty_tree(monkeypatch):
    answers = {"rev-parse": COMMIT, "status": " M README.md"}
    monkeypatch.setattr(record_bench, "_git", lambda *args: answers[args[0]])
    with pytest.raises(record_bench.RecordError, match="uncommitted changes"):
        record_bench.record("sim", [])


def test_record_bench_names_files_by_bench_and_variant(tmp_path):
    assert record_bench.result_path("sim", "cif", tmp_path) == tmp_path / "sim-cif.json"
    with pytest.raises(record_bench.RecordError, match="--variant"):
        record_bench.result_path("sim", "../x", tmp_path)


def test_the_records_table_follows_each_record_and_fails_when_one_changes(toy):
    record = _record(TOY_RESULT, load_1m={"before": 1.5, "after": 2.25}, duration_s=61.4)
    (toy / "results" / "toy.json").write_text(json.dumps(record | {"date_utc": "2026-12-03T1"}))
    table = readme_tables.records_table(toy / "results", "test", "results")
    assert "| [`toy.json`](results/toy.json) | `uma bench toy --json` | 0123456 " in table
    assert "| 1.5 -> 2.25 | 61 | 2026-12-03 |" in table
    document = toy / "measured.md"
    document.write_text(f"# m\n\n<!-- fig records -->\n{table}\n<!-- /fig -->\n\n| 0.5 | old |\n")
    assert readme_tables.check(document, toy / "results", False, "results") is None
    (toy / "results" / "toy.json").write_text(json.dumps(record | {"duration_s": 99.0}))
    problem = readme_tables.check(document, toy / "results", False, "results")
    assert problem.startswith("measured.md:6:"), problem


def test_a_records_block_naming_a_record_is_refused(toy):
    document = toy / "measured.md"
    document.write_text("<!-- fig records toy.json -->\n<!-- /fig -->\n")
    problem = readme_tables.check(document, toy / "results", strict=False)
    assert "names no record" in problem


def test_a_record_says_which_kind_of_machine_made_it(monkeypatch, tmp_path):
    answers = {"rev-parse": "abc123", "status": ""}
    monkeypatch.setattr(record_bench, "_git", lambda *args: answers[args[0]])
    monkeypatch.setattr(record_bench, "result_path", lambda name, variant: tmp_path / "x.json")
    done = subprocess.CompletedProcess([], 0, stdout=b'{"figure": 1}')
    monkeypatch.setattr(record_bench.subprocess, "run", lambda *a, **k: done)
    doc = json.loads(record_bench.record("sim", []).read_text())
    assert doc["result"] == {"figure": 1}
    assert doc["machine"]["class"] in ("avx512", "default")
    assert doc["machine"]["packages"]["numpy"]
