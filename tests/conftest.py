"""Shared fixtures: the real data beside the clone (`../shared/data`), skipped when absent.

Hypothesis profiles: `ci` is derandomised (the same examples every run, so a CI failure is
about the change, not the draw), chosen by `HYPOTHESIS_PROFILE=ci` (as `.ci/run` sets) or by
`CI` being set; local runs keep `dev`, which draws new examples each time.
"""

from __future__ import annotations

import os
from pathlib import Path

import pytest
from hypothesis import settings

import uma  # noqa: F401  pins OpenBLAS's kernels (uma.blas) before a test's import loads NumPy
from uma.paths import shared_data_dir

# No deadline: a test is never timed (speed is `uma bench`'s), and Hypothesis's 200 ms per
# example failed parsers' tests on a first call at load 6-12.
settings.register_profile("ci", derandomize=True, database=None, print_blob=True, deadline=None)
# Explicit: with `CI` set, Hypothesis loads its own derandomised `ci` profile at import, and a
# profile registered without values would inherit it.
settings.register_profile("dev", derandomize=False, deadline=None)
settings.load_profile(
    os.environ.get("HYPOTHESIS_PROFILE") or ("ci" if os.environ.get("CI") else "dev")
)


@pytest.fixture(scope="session", autouse=True)
def _uplink_store(tmp_path_factory):
    """Sweeps and benches keep sender streams in a store of the session's own (`UMA_CACHE`),
    never in the user's cache; a test that wants another sets its own."""
    previous = os.environ.get("UMA_CACHE")
    os.environ["UMA_CACHE"] = str(tmp_path_factory.mktemp("uma-cache"))
    yield
    if previous is None:
        os.environ.pop("UMA_CACHE", None)
    else:
        os.environ["UMA_CACHE"] = previous


@pytest.fixture(scope="session")
def shared_data() -> Path:
    """`../shared/data`; tests that take it skip on a clone without the shared folder."""
    root = shared_data_dir()
    if not root.is_dir():
        pytest.skip(f"shared data not found at {root}")
    return root


@pytest.fixture(scope="session")
def astronaut_clip(tmp_path_factory) -> Path:
    """Three frames as an H.264 clip (CRF 12), frame 1 the astronaut photograph, 0 and 2 black."""
    import av
    import cv2
    import numpy as np
    import skimage.data

    path = tmp_path_factory.mktemp("clip") / "astro.mp4"
    photo = cv2.cvtColor(skimage.data.astronaut(), cv2.COLOR_RGB2BGR)
    with av.open(str(path), "w", format="mp4") as container:
        stream = container.add_stream("libx264", rate=25)
        stream.width, stream.height, stream.pix_fmt = 512, 512, "yuv420p"
        stream.options = {"crf": "12", "preset": "ultrafast"}
        for k, picture in enumerate([np.zeros_like(photo), photo, np.zeros_like(photo)]):
            frame = av.VideoFrame.from_ndarray(picture, format="bgr24")
            frame.pts = k
            container.mux(stream.encode(frame))
        container.mux(stream.encode(None))
    return path


@pytest.fixture(scope="session")
def face_model():
    """The project's own wireframe (`load_model()`), read once: a `FaceModel` is frozen and its
    arrays are read-only, so tests can share it. Tests of reading the file call `load_model`."""
    from uma.face import load_model

    return load_model()


# A short run with two handovers (WLAN, 3G, GPRS) and an outage of the downlink: its playout
# rises and falls (the playout replay's tests in tests/sim and tests/bench).
PLAYOUT_SHORT = """\
name: playout-short
seed: 2
source: {kind: pattern, width: 176, height: 144, fps: 25}
route:
  - {technology: WLAN, duration_s: 3}
  - {technology: 3G, duration_s: 3}
  - {technology: GPRS, duration_s: 2}
receiver: {playout: adaptive}
faults:
  outages: [{start_s: 4.0, duration_s: 0.8}]
metrics: {workers: 0}
"""


@pytest.fixture(scope="session")
def playout_short_yaml() -> str:
    """`PLAYOUT_SHORT`: a scenario's YAML text."""
    return PLAYOUT_SHORT
