"""The CIF part of `uma bench init`: initialise on whole talking-head frames (352x288).

Units: milliseconds (wall clock around each fit), MDE in pixels of the CIF frame.

The stretch goal asks for a full initialisation of a CIF frame within one frame interval
(40 ms at 25 fps). Frames come from the talking-head source (the astronaut animated by the
model, with light changes and noise), whose ground truth is exact; the template is the source's
own content description; the face detector places the search on each frame.
"""

from __future__ import annotations

import time
from typing import Any

import numpy as np

__all__ = ["run_cif_bench"]


def run_cif_bench(frames: int, *, seed: int = 0) -> dict[str, Any]:
    """Fit `frames` talking-head frames with SAABs and the hybrid; times and MDE."""
    import cv2

    from uma.face.talking_head import TalkingHeadSource
    from uma.fit.cost import FitTemplate
    from uma.fit.fit import DetectorCalibration, detect, fit_face, initial_guess
    from uma.fit.mde import mde_px

    source = TalkingHeadSource(352, 288, seed=seed)
    description = source.description
    template = FitTemplate.build(description.model, description.gray, description.params)
    box = detect(description.gray)
    calibration = DetectorCalibration.from_template(template, box) if box else None
    rng = np.random.default_rng(seed)
    indices = np.sort(rng.choice(np.arange(25, 25 * 60), size=frames, replace=False))
    results: dict[str, dict[str, list[float]]] = {
        m: {"ms": [], "mde": []} for m in ("saabs", "hybrid")
    }
    failures = {m: 0 for m in results}
    warm = cv2.cvtColor(source.render_bgr(0), cv2.COLOR_BGR2GRAY).astype(np.float32)
    fit_face(template, warm, method="hybrid", calibration=calibration, rng=0)
    for index in indices:
        gray = cv2.cvtColor(source.render_bgr(int(index), rng=rng), cv2.COLOR_BGR2GRAY).astype(
            np.float32
        )
        truth = source.ground_truth(int(index))["params"]
        for method in results:
            begin = time.perf_counter()
            guess = initial_guess(template, gray, calibration)
            fit = (
                fit_face(
                    template, gray, method=method, start=guess[0], box=guess[1], rng=int(index)
                )
                if guess
                else guess
            )
            elapsed = (time.perf_counter() - begin) * 1000.0
            if not fit:
                failures[method] += 1
                continue
            results[method]["ms"].append(elapsed)
            results[method]["mde"].append(mde_px(template.model, fit.params, truth))
    out: dict[str, Any] = {
        "frames": frames,
        "image": "352x288",
        "template_pixels": template.raster.size,
    }
    for method, values in results.items():
        out[method] = {
            "time_median_ms": round(float(np.median(values["ms"])), 3) if values["ms"] else None,
            "mde_median_px": round(float(np.median(values["mde"])), 4) if values["mde"] else None,
            "mde_p95_px": round(float(np.percentile(values["mde"], 95)), 4)
            if values["mde"]
            else None,
            "failures": failures[method],
        }
    return out
