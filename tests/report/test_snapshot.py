"""`python -m uma.report.snapshot`: source and each run's shown picture side by side at one
instant, and one line with exit 2 (no file) for an instant the run never reaches."""

import cv2

from uma.report.snapshot import main

SCENARIO = """name: {name}
seed: 1
source: {{kind: pattern, width: 176, height: 144, fps: 25}}
route:
  - {{technology: WLAN, duration_s: 0.5}}
"""


def _scenario(tmp_path, name: str):
    path = tmp_path / f"{name}.yaml"
    path.write_text(SCENARIO.format(name=name))
    return path


def test_the_png_holds_the_source_and_the_run_side_by_side(tmp_path):
    out = tmp_path / "shot.png"
    assert main([str(_scenario(tmp_path, "one")), "--at-s", "0.3", "--out", str(out)]) == 0
    image = cv2.imread(str(out))
    assert image.shape[:2] == (144, 2 * 176)
    source, shown = image[:, :176].astype(int), image[:, 176:352].astype(int)
    # the run shows the picture (not a black panel), close to the source
    assert shown[40:].mean() > 20 and abs(source[40:] - shown[40:]).mean() < 20


def test_an_instant_after_the_run_is_one_line_and_no_file(tmp_path, capsys):
    out = tmp_path / "shot.png"
    assert main([str(_scenario(tmp_path, "one")), "--at-s", "9", "--out", str(out)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith("uma: error: one: no display instant at 9 s")
    assert not out.exists()
