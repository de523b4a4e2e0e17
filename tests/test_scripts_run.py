"""The scripts in `scripts/` run on the current package: the docs quote their figures with their
commands, so a reader must be able to run them again.

Fast: every script imports as a module and its command line parses `--help` (exit 0), and
every `uma` name a script imports, or reads or sets on a `uma` module or class it imported,
exists (a script's package imports sit inside its functions, where `--help` does not reach;
a patch set on a renamed name would be silently ignored). Slow: every script whose smallest
real run takes under about 10 s runs at that setting in a process of its own, from the
repository root with the checkout on `PYTHONPATH` (as their docstrings say), and its output is
checked for shape (keys, rows, files), never for figures; a run that warns that NumPy or
OpenCV came before `import uma` fails (a missed pin gives other figures than the bench's).
"""

from __future__ import annotations

import ast
import importlib
import json
import os
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
SCRIPTS = ROOT / "scripts"
sys.path.insert(0, str(SCRIPTS))  # the scripts import their siblings (links_settings, ...)

NAMES = sorted(p.stem for p in SCRIPTS.glob("*.py"))
# Modules of the README's renderers, with no command line: imported only.
LIBRARIES = {"readme_blocks", "readme_seeds", "readme_targets"}
# `write` or `check`, no `--help` (tests/test_readme_figures.py runs its `check`).
OWN_ARGV = {"readme_tables"}


@pytest.mark.parametrize("name", NAMES)
def test_a_script_imports_and_parses_help(name, monkeypatch, capsys):
    module = importlib.import_module(name)
    if name in LIBRARIES | OWN_ARGV:
        return
    monkeypatch.setattr(sys, "argv", [str(SCRIPTS / f"{name}.py"), "--help"])
    with pytest.raises(SystemExit) as stopped:
        module.main()
    assert stopped.value.code == 0
    assert capsys.readouterr().out.startswith("usage:")


def uma_references(path: Path) -> list[tuple[int, str, str]]:
    """(line, dotted owner, name) of every `from uma... import name` in `path`, and of every
    attribute read or set on a name such an import (or `import uma... as x`) bound."""
    tree = ast.parse(path.read_text())
    out, bound = [], {}
    for node in ast.walk(tree):
        if isinstance(node, ast.ImportFrom) and node.level == 0 and node.module:
            if node.module.split(".")[0] == "uma":
                for alias in node.names:
                    out.append((node.lineno, node.module, alias.name))
                    bound[alias.asname or alias.name] = f"{node.module}.{alias.name}"
        elif isinstance(node, ast.Import):
            for alias in node.names:
                if alias.name.split(".")[0] == "uma" and alias.asname:
                    bound[alias.asname] = alias.name
    for node in ast.walk(tree):
        value = node.value if isinstance(node, ast.Attribute) else None
        if isinstance(value, ast.Name) and value.id in bound:
            out.append((node.lineno, bound[value.id], node.attr))
    return out


def resolve(dotted: str):
    """The module, or the object inside a module, that `dotted` names."""
    try:
        return importlib.import_module(dotted)
    except ModuleNotFoundError:
        owner, _, name = dotted.rpartition(".")
        return getattr(resolve(owner), name)


def _has(owner: str, name: str) -> bool:
    try:
        obj = resolve(owner)
    except (ModuleNotFoundError, AttributeError):  # a module gone or moved
        return False
    if hasattr(obj, name):
        return True
    try:  # a submodule not imported by its package
        importlib.import_module(f"{owner}.{name}")
    except ModuleNotFoundError:
        return False
    return True


@pytest.mark.parametrize("name", NAMES)
def test_every_uma_name_a_script_uses_exists(name):
    path = SCRIPTS / f"{name}.py"
    missing = [
        f"{path.name}:{line}: {owner}.{attr}"
        for line, owner, attr in uma_references(path)
        if not _has(owner, attr)
    ]
    assert not missing, "\n".join(missing)


# --- slow: the cheapest real runs ----------------------------------------------------------

TRACE = "traces/nyu-mets/BB62.txt.gz"  # under ../shared/data
SHORT_ROUTE = json.dumps(  # the model codec's technologies, after a start where H.264 runs
    [{"technology": t, "duration_s": s} for t, s in (("3G", 2), ("GPRS", 4), ("GSM", 4))]
)
TINY = """\
name: tiny
seed: 1
source: {kind: pattern, width: 176, height: 144, fps: 25}
route: [{technology: 3G, duration_s: 2}]
metrics: {ssim: false}
"""


def run_script(name: str, *args, timeout: float = 180) -> str:
    """`python scripts/NAME.py ARGS` from the repository root; its stdout (exit 0 asserted)."""
    env = {**os.environ, "PYTHONPATH": str(ROOT)}
    done = subprocess.run(
        [sys.executable, str(SCRIPTS / f"{name}.py"), *map(str, args)],
        cwd=ROOT, env=env, capture_output=True, text=True, timeout=timeout,
    )  # fmt: skip
    assert done.returncode == 0, done.stderr[-3000:]
    assert "import uma first" not in done.stderr, done.stderr[-3000:]
    return done.stdout


@pytest.fixture(scope="module")
def short_run(tmp_path_factory, playout_short_yaml) -> Path:
    """A `uma run` folder of the tests' short run with handovers (frames.csv, events.csv)."""
    folder = tmp_path_factory.mktemp("short-run")
    (folder / "short.yaml").write_text(playout_short_yaml)
    command = [sys.executable, "-m", "uma", "run", str(folder / "short.yaml"), "--quiet"]
    subprocess.run([*command, "--out", str(folder / "run")], cwd=ROOT, check=True, timeout=120)
    return folder / "run"


@pytest.mark.slow
@pytest.mark.parametrize("name", ["links_settings", "freeze_causes"])
def test_a_links_case_script_writes_its_rows(name, shared_data, tmp_path):
    out = tmp_path / "out.json"
    case = f"{shared_data / TRACE}:0:5"
    run_script(name, "--case", case, "--engines", "uma", "--workers", 1, "--json", out)
    written = json.loads(out.read_text())
    rows = written["rows"] if name == "links_settings" else [r["row"] for r in written["runs"]]
    assert len(rows) == 1 and {"delay_p95_ms", "ssim_db_unfrozen", "freeze_ratio"} <= set(rows[0])
    if name == "freeze_causes":
        assert set(written["runs"][0]["causes"]) <= set(importlib.import_module(name).CAUSES)


@pytest.mark.slow
def test_delay_tail_and_ssim_gap_keep_their_logs(shared_data, tmp_path):
    case = f"{shared_data / TRACE}:0:5"
    common = ("--case", case, "--engines", "uma", "--workers", 1)
    said = run_script("delay_tail", *common, "--out", tmp_path / "tail")
    assert "BB62.txt-0-uma p95" in said and "tail instants" in said
    assert {p.name for p in (tmp_path / "tail").iterdir()} == {
        "BB62.txt-0-uma.csv",
        "BB62.txt-0-uma-events.txt",
    }
    said = run_script("ssim_gap", *common, "--out", tmp_path / "gap")
    assert "== BB62.txt 0+5 s" in said and "rung  size  time  unfrozen" in said
    assert (tmp_path / "gap" / "BB62.txt-0-uma.npz").is_file()


@pytest.mark.slow
def test_playout_replay_is_the_run_s_display(short_run):
    said = run_script("playout_replay", short_run / "frames.csv", "--set", "calm_s=15")
    rows = [line for line in said.splitlines() if line.startswith("  ")]
    assert len(rows) == 2 and all("[as the run" in row for row in rows), said


@pytest.mark.slow
def test_keyframe_free_prints_each_path(short_run):
    said = json.loads(run_script("keyframe_free", short_run, "--clip", "talking-head", "--json"))
    paths = said["talking-head"]
    assert set(paths) == {"reopen", "set_target", "set_target-top", "set_target-mid"}
    assert {"h264_kbit", "keyframe_bits_share", "keyframes", "psnr_db_mean"} <= set(paths["reopen"])


@pytest.mark.slow
def test_machine_variants_and_seam_identity_find_the_same_bytes(tmp_path):
    (tmp_path / "tiny.yaml").write_text(TINY)
    said = run_script("machine_variants", tmp_path / "tiny.yaml")
    assert said.splitlines() == [
        "tiny native: same",
        "tiny numba-generic: same",
        "tiny numpy-no-x86-v3: same",
    ]
    assert "recorded" in run_script("seam_identity", "record", tmp_path / "seam", "--only",
                                    "mbc-refused")  # fmt: skip
    said = run_script("seam_identity", "check", tmp_path / "seam", "--only", "mbc-refused")
    assert said.count(": identical (") == 3


@pytest.mark.slow
def test_real_stretch_runs_its_segment(shared_data, tmp_path):
    run_script("real_stretch", shared_data / TRACE, 0, 2, tmp_path)
    assert (tmp_path / "scenario-in.yaml").is_file()
    assert "freeze_ratio" in json.loads((tmp_path / "run" / "metrics.json").read_text())


@pytest.mark.slow
def test_tracking_windows_counts(tmp_path):
    said = json.loads(run_script("tracking_windows", "--only", "talking-head", "--head-frames",
                                20, "--json"))  # fmt: skip
    assert said["talking-head"]["frames"] == 20
    assert {"reinits", "failures", "worst_window_reinits", "events"} <= set(said["talking-head"])


@pytest.mark.slow
def test_mbc_cpu_scripts_print_their_stages():
    said = json.loads(run_script("mbc_stage_cpu", "--frames", 10))
    assert set(said["talking-head"]) == {"track", "light", "body", "decode_render", "sum"}
    said = json.loads(run_script("mbc_draw_cpu", "--frames", 10, "--passes", 1, "--clips",
                                "talking-head"))  # fmt: skip
    assert {"receiver", "mirror", "sets", "digests"} == set(said["talking-head"])
    said = run_script("mbc_threads", "--reps", 1, "--frames", 5).splitlines()
    medians = [json.loads(line) for line in said if line.startswith('{"medians"')]
    assert medians and {"stages_ms", "model_path_cpu_ms"} <= set(medians[0])


@pytest.mark.slow
def test_mbc_bench_scripts_print_each_display(tmp_path):
    head = ("--start", 0, "--frames", 10, "--clips", "talking-head")
    said = run_script("mbc_camera", *head, "--settings", "off")
    for name in ("quantised", "mbc_refresh_lowest", "mbc_refresh_second", "h264_lowest"):
        assert f"talking-head camera off {name}: " in said
    said = run_script("refresh_variants", *head, "--set", "fresh")
    assert "talking-head previous_r0: " in said and "talking-head f12.5_vp8_r1: " in said
    run_script("mbc_look", "talking-head", tmp_path / "look.png", "--frames", 10, "--frame", 5)
    assert (tmp_path / "look.png").stat().st_size > 0
    said = run_script("mbc_anatomy", *head[2:], "--worst", 1, "--png-dir", tmp_path / "anat")
    assert any(line.startswith("box ") and "pooled PSNR" in line for line in said.splitlines())
    assert len(list((tmp_path / "anat").glob("talking-head-*.png"))) == 1


@pytest.mark.slow
def test_mbc_drawn_splits_akiyo_s_box(shared_data):
    said = run_script("mbc_drawn", "--frames", 10, "--clips", "akiyo")
    for kind in ("plate seen", "plate filled", "torso", "halo and head ring"):
        assert f"\n  {kind:20s} " in said
    assert "bound_box: MSE best of" in said


@pytest.mark.slow
def test_mbc_transformed_prints_its_table(shared_data, tmp_path):
    said = run_script("mbc_transformed", "--frames", 5, "--only", "mirrored", "--out", tmp_path)
    rows = [line for line in said.splitlines() if line.startswith("| ")]
    assert rows[0].startswith("| clip | re-inits / lost |")
    assert [row.split(" | ")[0] for row in rows[1:]] == ["| akiyo", "| mirrored"]


@pytest.mark.slow
def test_mbc_canvas_split_and_ring_parts_split_by_technology(tmp_path):
    import yaml

    run_script("mbc_canvas_split", "--set", f"route={SHORT_ROUTE}", "--out", tmp_path / "split")
    split = json.loads((tmp_path / "split" / "split.json").read_text())
    assert set(split) == {"GPRS", "GSM"}
    assert all({"instants", "uma_psnr_face_db", "h264_psnr_face_db"} <= set(row)
               for rows in split.values() for row in rows.values())  # fmt: skip
    assert (tmp_path / "split" / "uma_frames.npz").is_file()
    scenario = yaml.safe_load((ROOT / "scenarios/stockholm-uppsala.yaml").read_text())
    scenario["route"] = json.loads(SHORT_ROUTE)
    (tmp_path / "short.yaml").write_text(yaml.safe_dump(scenario))
    run_script("mbc_ring_parts", tmp_path / "short.yaml", "--out", tmp_path / "ring")
    parts = json.loads((tmp_path / "ring" / "ring_parts.json").read_text())
    assert parts and all(key.split()[0] in {"GPRS", "GSM"} for key in parts)
