"""The small sweep both sweep test modules run: a base scenario and a 2 x 2 grid."""

BASE = """\
name: base
seed: 1
source: {kind: pattern, width: 96, height: 64, fps: 25}
route:
  - {technology: 3G, duration_s: 1.0, trace: good.csv}
  - {technology: GPRS, duration_s: 1.0}
"""
EXPERIMENT = """\
name: grid
base: base.yaml
grid:
  engine.policy: [throughput, oracle]
  receiver.playout_delay_ms: [150, 400]
"""
