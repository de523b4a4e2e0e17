"""A tiny scenario and a one-point experiment over it, for the command line's folder tests."""

BASE = """\
name: base
seed: 1
source: {kind: pattern, width: 96, height: 64, fps: 25}
route:
  - {technology: 3G, duration_s: 0.4}
"""
EXPERIMENT = "name: grid\nbase: base.yaml\ngrid:\n  engine.policy: [throughput]\n"
