"""Run `scripts/links_settings.py` or `uma run` with the rate policy's climb changed.

`python scripts/climb_jump.py links [--climb=MODE] --case TRACE:OFFSET_S:DURATION_S ...` runs
`scripts/links_settings.py` (same arguments) with `uma.engine.position.CLIMB` set to MODE (one
of `uma.engine.policy.CLIMBS`; "stream" when not given) in every worker; `python
scripts/climb_jump.py run [--climb=MODE] [SCENARIO.yaml] [--out DIR] ...` runs `uma run` with
it set. `--climb=step` is the engine's default climb (a side-by-side baseline). Run from the repository root with the checkout on `PYTHONPATH`
(docs/rate-control.md, branch rc23).
"""

from __future__ import annotations

import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))

import links_settings  # noqa: E402

CLIMB = "stream"
_plain_case_row = links_settings._case_row


def _case_row(job: tuple) -> tuple:
    import uma.engine.position as position

    position.CLIMB = CLIMB
    return _plain_case_row(job)


def main(argv: list[str]) -> int:
    global CLIMB
    command, rest = argv[0], argv[1:]
    if rest and rest[0].startswith("--climb="):
        CLIMB, rest = rest[0].partition("=")[2], rest[1:]
    if command == "links":
        links_settings._case_row = _case_row
        return links_settings.main(rest)
    if command == "run":
        import uma.engine.position as position
        from uma.cli import main as uma_main

        position.CLIMB = CLIMB
        return uma_main(["run", *rest])
    raise SystemExit(f"climb_jump: expected 'links' or 'run', got {command!r}")


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
