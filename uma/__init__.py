"""uma: a video conference over a roaming mobile downlink, simulated with real codecs and traces.

Sub-packages hold one job each (see README.md): `traces` (bandwidth traces and routes), `video`
(H.264 over PyAV, frame sources), `face` (wireframe model and renderer), `fit` (SAABs and
Gauss-Newton), `engine` (pure UMA decisions), `sim` (the SimPy world), `metrics`, `bench`, `cli`.
Import those directly; this top level stays light so `uma --help` is instant.
"""

from uma.errors import ConfigError, FaceError, RunError, TraceError, UmaError, VideoError

__version__ = "0.1.0"

__all__ = [
    "UmaError",
    "ConfigError",
    "TraceError",
    "VideoError",
    "FaceError",
    "RunError",
    "__version__",
]
