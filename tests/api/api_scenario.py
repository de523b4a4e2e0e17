"""The tiny scenario the API tests run: a 96x64 pattern through 3G into GPRS, 2.4 s."""

TINY = """\
name: tiny
seed: 2
source: {kind: pattern, width: 96, height: 64, fps: 25}
route:
  - {technology: 3G, duration_s: 1.2}
  - {technology: GPRS, duration_s: 1.2}
"""
