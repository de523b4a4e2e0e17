"""`uma bench init`: automatic face-model initialisation, five methods on the same cases.

Units: MDE in pixels at 92x112, times in milliseconds of wall clock per initialisation (one
core; time.perf_counter around each call, never inside the algorithms), evaluations of the cost.

Methods: SAABs (NCC), SAABs with per-patch illumination compensation, Gauss-Newton from the
detector's start, scipy's dual_annealing on the NCC cost with exactly SAABs' evaluation budget
(stopped when it is spent, since scipy's `maxfun` is a soft limit), and the hybrid (SAABs'
global pose search in two views of the images, a third when the match is poor, the best
polished by Gauss-Newton; a median 645 evaluations to SAABs' 508, see `uma.fit.hybrid`). All start from the same
detector proposal (or, where the detector misses, the template's placement) in the same box.
The detector runs once per case, outside the timed calls; its median time is reported apart.
A fit that returns a failure counts with the error of its start.
"""

from __future__ import annotations

import time
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from uma.bench.init_cases import (
    IMAGE_SIZE,
    Case,
    is_large_pose,
    light_angle_deg,
    load_templates,
    make_cases,
)

__all__ = [
    "InitBenchConfig",
    "run_init_bench",
    "METHOD_NAMES",
    "PAPER_SPLIT",
    "SUCCESS_PX",
    "SUBSETS",
    "paper_split",
]

METHOD_NAMES = ("saabs", "saabs_ic", "gauss_newton", "dual_annealing", "hybrid")
# Also timed: SAABs with the paper's split of its loops, for the speed target "400 + 100 loops".
PAPER_SPLIT = "saabs_400_100"
SUCCESS_PX = 1.5
# Subsets reported beside "all": key -> which cases.
SUBSETS = {
    "large_pose": lambda row: row["large_pose"],
    "same_light": lambda row: row["light_deg"] is None,
    "light_change": lambda row: row["light_deg"] is not None,
    "light_within_25deg": lambda row: row["light_deg"] is not None and row["light_deg"] <= 25,
    "light_beyond_25deg": lambda row: row["light_deg"] is not None and row["light_deg"] > 25,
}


@dataclass(frozen=True)
class InitBenchConfig:
    cases: int = 80
    faces: Path | None = None
    yale: Path | None = None
    seed: int = 0
    cif_frames: int = 10

    def __post_init__(self) -> None:
        if self.cases < 1 or self.cif_frames < 0:
            raise ValueError(
                f"bench init: cases >= 1 and cif_frames >= 0 expected, got {self.cases}, {self.cif_frames}"
            )


def _start(case: Case):
    from uma.fit.fit import initial_guess

    image = case.image.astype(np.float32)
    guess = initial_guess(case.template.fit, image, case.template.calibration)
    if guess:
        return guess, True
    return initial_guess(case.template.fit, image, None), False


class _Spent(Exception):
    """The evaluation budget is used up."""


def _dual_annealing(case: Case, start, box, budget: int, rng: np.random.Generator):
    from scipy.optimize import dual_annealing

    from uma.fit.cost import Cost
    from uma.fit.result import FitResult

    cost = Cost(case.template.fit, case.image.astype(np.float32))
    best = {"x": np.asarray(start, dtype=np.float64), "f": np.inf}

    def objective(x: np.ndarray) -> float:
        # maxfun is a soft limit (its local searches overrun it): stop exactly at the budget.
        if cost.evaluations >= budget:
            raise _Spent
        value = float(cost(x))
        if value < best["f"]:
            best["x"], best["f"] = np.array(x, dtype=np.float64), value
        return value

    iterations = 0
    try:
        result = dual_annealing(
            objective, box.bounds, maxfun=budget, x0=start, seed=int(rng.integers(2**31))
        )
        iterations = int(result.nit)
    except _Spent:
        pass
    return FitResult(
        params=best["x"], cost=best["f"], evaluations=cost.evaluations, iterations=iterations
    )


def paper_split():
    """SAABs' settings with the paper's 400 global + 100 local loops (50 x 8 and 20 x 5)."""
    from dataclasses import replace

    from uma.fit.saabs import SaabsConfig

    default = SaabsConfig()
    return replace(
        default,
        global_phase=replace(default.global_phase, steps=50, tries=8),
        local_phase=replace(default.local_phase, steps=20, tries=5),
    )


def _run_method(name: str, case: Case, start, box, rng: np.random.Generator, budget: int):
    from uma.fit.fit import fit_face

    if name == "dual_annealing":
        return _dual_annealing(case, start, box, budget, rng)
    image = case.image.astype(np.float32)
    if name == PAPER_SPLIT:
        return fit_face(
            case.template.fit,
            image,
            method="saabs",
            start=start,
            box=box,
            rng=rng,
            saabs_config=paper_split(),
        )
    return fit_face(case.template.fit, image, method=name, start=start, box=box, rng=rng)


def _summary(rows: list[dict[str, Any]], name: str) -> dict[str, Any]:
    if not rows:
        keys = ("mde_median_px", "mde_p95_px", "success_rate", "time_median_ms")
        return {**dict.fromkeys(keys), "evaluations_median": None, "cases": 0, "failures": 0}
    mde = np.array([row[name]["mde_px"] for row in rows])
    spent = [row[name]["evaluations"] for row in rows if not row[name]["failed"]]
    return {
        "mde_median_px": round(float(np.median(mde)), 4),
        "mde_p95_px": round(float(np.percentile(mde, 95)), 4),
        "success_rate": round(float(np.mean(mde < SUCCESS_PX)), 4),
        "time_median_ms": round(float(np.median([row[name]["ms"] for row in rows])), 3),
        # Over the fits that returned a result (a failure does not say what it spent).
        "evaluations_median": int(np.median(spent)) if spent else None,
        "cases": len(rows),
        "failures": int(sum(row[name]["failed"] for row in rows)),
    }


def _case_row(model, case, index: int, seed: int, budget: int) -> tuple[dict[str, Any], float]:
    """(one case's row: its pose and every method's fit, the detector's milliseconds)."""
    from uma.fit.mde import mde_px

    begin = time.perf_counter()
    (start, box), found = _start(case)
    detector_ms = (time.perf_counter() - begin) * 1000.0
    row: dict[str, Any] = {
        "case": case.name,
        "yaw_deg": round(case.yaw_deg, 2),
        "pitch_deg": round(case.pitch_deg, 2),
        "roll_deg": round(case.roll_deg, 2),
        "shift_frac": round(case.shift_frac, 4),
        "lighting": case.lighting,
        "light_deg": light_angle_deg(case.lighting),
        "large_pose": is_large_pose(case),
        "detected": bool(found),
        "start_mde_px": round(mde_px(model, start, case.truth), 4),
    }
    for name in (*METHOD_NAMES, PAPER_SPLIT):
        method_rng = np.random.default_rng([seed, index])
        begin = time.perf_counter()
        result = _run_method(name, case, start, box, method_rng, budget)
        elapsed_ms = (time.perf_counter() - begin) * 1000.0
        params = result.params if result else start
        row[name] = {
            "mde_px": round(mde_px(model, params, case.truth), 4),
            "ms": round(elapsed_ms, 3),
            "evaluations": int(result.evaluations) if result else 0,
            "failed": not result,
            "reason": None if result else result.reason,
        }
    return row, detector_ms


def _methods(rows: list[dict[str, Any]]) -> dict[str, Any]:
    """Each method's summary over every case, and over each subset of them."""
    methods = {}
    for name in METHOD_NAMES:
        summary = _summary(rows, name)
        for key, pick in SUBSETS.items():
            summary[key] = _summary([row for row in rows if pick(row)], name)
        methods[name] = summary
    return methods


def run_init_bench(config: InitBenchConfig, *, progress=None) -> dict[str, Any]:
    """Build the cases, fit each with every method, and summarise with the keys of docs/benchmarks.md."""
    from uma.bench.init_cif import run_cif_bench
    from uma.face.load import load_model
    from uma.fit.saabs import SaabsConfig

    model = load_model()
    templates = load_templates(model, faces=config.faces, yale=config.yale)
    rng = np.random.default_rng(config.seed)
    cases = make_cases(templates, config.cases, rng=rng)
    budget = SaabsConfig().budget
    # Warm the compiled kernels so no method pays for compilation in its timing.
    (start, box), _ = _start(cases[0])
    for name in (*METHOD_NAMES, PAPER_SPLIT):
        _run_method(name, cases[0], start, box, np.random.default_rng(0), 50)

    rows, detector_ms = [], []
    for index, case in enumerate(cases):
        row, ms = _case_row(model, case, index, config.seed, budget)
        rows.append(row)
        detector_ms.append(ms)
        if progress is not None:
            progress(index + 1, len(cases))
    cif = run_cif_bench(config.cif_frames, seed=config.seed) if config.cif_frames > 0 else None
    return {
        "cases": len(cases),
        "image": f"{IMAGE_SIZE[0]}x{IMAGE_SIZE[1]}",
        "seed": config.seed,
        "templates": [t.name for t in templates],
        "large_pose_cases": int(sum(r["large_pose"] for r in rows)),
        "large_pose_definition": "rotation from the template's pose above 20 deg "
        "(yaw, pitch and roll combined) or a shift above 8 % of the face width",
        "detector_found": int(sum(r["detected"] for r in rows)),
        "detector_median_ms": round(float(np.median(detector_ms)), 3),
        "evaluation_budget": budget,
        "success_px": SUCCESS_PX,
        "methods": _methods(rows),
        PAPER_SPLIT: _summary(rows, PAPER_SPLIT),
        "cif": cif,
        "rows": rows,
    }
