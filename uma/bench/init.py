"""`uma bench init`: automatic face-model initialisation, five methods on the same cases.

Units: MDE in pixels at 92x112, times in milliseconds of wall clock per initialisation (one
core; measured around each call, never inside the algorithms), evaluations of the cost.

Methods: SAABs (NCC), SAABs with per-patch illumination compensation, Gauss-Newton from the
detector's start, scipy's dual_annealing on the same NCC cost with SAABs' evaluation budget,
and the hybrid (SAABs' global pose search, then Gauss-Newton). All start from the same
detector proposal (or, where the detector misses, the template's placement) in the same box.
"""

from __future__ import annotations

import time
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from uma.bench.init_cases import IMAGE_SIZE, Case, is_large_pose, load_templates, make_cases

__all__ = ["InitBenchConfig", "run_init_bench", "format_table", "METHOD_NAMES"]

METHOD_NAMES = ("saabs", "saabs_ic", "gauss_newton", "dual_annealing", "hybrid")
SUCCESS_PX = 1.5


@dataclass(frozen=True)
class InitBenchConfig:
    cases: int = 40
    faces: Path | None = None
    yale: Path | None = None
    seed: int = 0
    cif_frames: int = 10


def _start(case: Case):
    from uma.fit.fit import initial_guess

    guess = initial_guess(
        case.template.fit, case.image.astype(np.float32), case.template.calibration
    )
    if guess:
        return guess, True
    return initial_guess(case.template.fit, case.image.astype(np.float32), None), False


def _dual_annealing(case: Case, start, box, budget: int, rng: np.random.Generator):
    from scipy.optimize import dual_annealing

    from uma.fit.cost import Cost
    from uma.fit.saabs import FitResult

    cost = Cost(case.template.fit, case.image.astype(np.float32))
    # maxfun is a soft limit (the local searches overrun it): stop at the budget, as SAABs does.
    result = dual_annealing(
        lambda x: float(cost(x)),
        box.bounds,
        maxfun=budget,
        x0=start,
        seed=int(rng.integers(2**31)),
        callback=lambda x, f, context: cost.evaluations >= budget,
    )
    return FitResult(
        params=result.x,
        cost=float(result.fun),
        evaluations=cost.evaluations,
        iterations=int(result.nit),
    )


def _run_method(name: str, case: Case, start, box, rng: np.random.Generator, budget: int):
    from uma.fit.fit import fit_face

    image = case.image.astype(np.float32)
    if name == "dual_annealing":
        return _dual_annealing(case, start, box, budget, rng)
    result = fit_face(case.template.fit, image, method=name, start=start, box=box, rng=rng)
    if not result:
        return None
    return result


def _summary(mde: list[float], times_ms: list[float], evaluations: list[int]) -> dict[str, Any]:
    if not mde:
        return {
            "mde_median_px": None,
            "mde_p95_px": None,
            "success_rate": None,
            "time_median_ms": None,
            "evaluations_median": None,
        }
    values = np.array(mde)
    return {
        "mde_median_px": round(float(np.median(values)), 4),
        "mde_p95_px": round(float(np.percentile(values, 95)), 4),
        "success_rate": round(float(np.mean(values < SUCCESS_PX)), 4),
        "time_median_ms": round(float(np.median(times_ms)), 3),
        "evaluations_median": int(np.median(evaluations)),
    }


def run_init_bench(config: InitBenchConfig, *, progress=None) -> dict[str, Any]:
    """Build the cases, fit each with every method, and summarise as CONVENTIONS.md asks."""
    from uma.face.model import load_model
    from uma.fit.mde import mde_px
    from uma.fit.saabs import SaabsConfig

    model = load_model()
    templates = load_templates(model, faces=config.faces, yale=config.yale)
    rng = np.random.default_rng(config.seed)
    cases = make_cases(templates, config.cases, rng=rng)
    defaults = SaabsConfig()
    budget = defaults.global_phase.budget + defaults.local_phase.budget
    # Warm the compiled kernels so no method pays for compilation in its timing.
    warm = cases[0]
    start, box = _start(warm)[0]
    for name in METHOD_NAMES:
        _run_method(name, warm, start, box, np.random.default_rng(0), 50)

    rows = []
    per_method = {
        name: {"mde": [], "ms": [], "ev": [], "large": [], "lit": []} for name in METHOD_NAMES
    }
    detected = 0
    for index, case in enumerate(cases):
        (start, box), found = _start(case)
        detected += found
        row = {
            "case": case.name,
            "yaw_deg": case.yaw_deg,
            "pitch_deg": case.pitch_deg,
            "roll_deg": case.roll_deg,
            "lighting": case.lighting,
            "large_pose": is_large_pose(case),
        }
        for name in METHOD_NAMES:
            method_rng = np.random.default_rng([config.seed, index])
            begin = time.perf_counter()
            result = _run_method(name, case, start, box, method_rng, budget)
            elapsed_ms = (time.perf_counter() - begin) * 1000.0
            # A failed fit counts with the start's error: the method gave no better answer.
            params = result.params if result is not None else start
            error = mde_px(model, params, case.truth)
            row[name] = error
            stats = per_method[name]
            stats["mde"].append(error)
            stats["ms"].append(elapsed_ms)
            stats["ev"].append(result.evaluations if result is not None else 0)
            stats["large"].append(is_large_pose(case))
            stats["lit"].append(case.lighting != "same")
        rows.append(row)
        if progress is not None:
            progress(index + 1, len(cases))

    methods = {}
    for name, stats in per_method.items():
        summary = _summary(stats["mde"], stats["ms"], stats["ev"])
        subsets = (
            ("large_pose", "large", True),
            ("same_light", "lit", False),
            ("light_change", "lit", True),
        )
        for key, flag, want in subsets:
            chosen = {
                k: [v for v, f in zip(stats[k], stats[flag], strict=True) if f == want]
                for k in ("mde", "ms", "ev")
            }
            summary[key] = _summary(chosen["mde"], chosen["ms"], chosen["ev"])
        methods[name] = summary
    from uma.bench.init_cif import run_cif_bench

    cif = run_cif_bench(config.cif_frames, seed=config.seed) if config.cif_frames > 0 else None
    return {
        "cases": len(cases),
        "image": f"{IMAGE_SIZE[0]}x{IMAGE_SIZE[1]}",
        "templates": [t.name for t in templates],
        "large_pose_cases": int(sum(r["large_pose"] for r in rows)),
        "detector_found": detected,
        "evaluation_budget": budget,
        "methods": methods,
        "cif": cif,
        "rows": rows,
    }


def format_table(result: dict[str, Any], *, max_rows: int = 40) -> str:
    """Table I style: one row per case (MDE of each method), then the summary."""
    names = list(METHOD_NAMES)
    header = f"{'case':<22}{'yaw':>6}{'pitch':>6}{'roll':>6}  " + "".join(f"{n:>15}" for n in names)
    lines = [
        f"uma bench init: {result['cases']} cases at {result['image']} from {len(result['templates'])} "
        f"templates ({result['large_pose_cases']} large-pose); detector found {result['detector_found']}",
        "MDE (px, RMS per model point) against the known pose",
        "",
        header,
    ]
    for row in result["rows"][:max_rows]:
        mark = "*" if row["large_pose"] else " "
        cells = "".join(f"{row[n]:>15.3f}" for n in names)
        lines.append(
            f"{row['case'][:21]:<21}{mark}{row['yaw_deg']:>6.1f}{row['pitch_deg']:>6.1f}{row['roll_deg']:>6.1f}  {cells}"
        )
    if len(result["rows"]) > max_rows:
        lines.append(f"... {len(result['rows']) - max_rows} more cases (see --json)")
    lines += ["", "(* large pose)", ""]
    lines.append(f"{'':<48}" + "".join(f"{n:>15}" for n in names))
    for label, key in (
        ("median MDE (px)", "mde_median_px"),
        ("95th percentile MDE (px)", "mde_p95_px"),
        (f"success (MDE < {SUCCESS_PX} px)", "success_rate"),
        ("median time (ms)", "time_median_ms"),
        ("median cost evaluations", "evaluations_median"),
    ):
        for scope, pick in (
            ("all", lambda m: m),
            ("large pose", lambda m: m["large_pose"]),
            ("same light (ORL)", lambda m: m["same_light"]),
            ("light change (Yale B)", lambda m: m["light_change"]),
        ):
            cells = "".join(f"{_fmt(pick(result['methods'][n])[key]):>15}" for n in names)
            lines.append(f"{label + ', ' + scope:<48}{cells}")
    cif = result.get("cif")
    if cif:
        lines += [
            "",
            f"Whole CIF talking-head frames ({cif['frames']} frames, {cif['template_pixels']} template pixels; "
            "stretch goal: 40 ms a frame)",
        ]
        for method in ("saabs", "hybrid"):
            m = cif[method]
            lines.append(
                f"  {method:<8} median {_fmt(m['time_median_ms'])} ms, MDE median {_fmt(m['mde_median_px'])} px, "
                f"p95 {_fmt(m['mde_p95_px'])} px, failures {m['failures']}"
            )
    return "\n".join(lines)


def _fmt(value) -> str:
    if value is None:
        return "n/a"
    return f"{value:.3f}" if isinstance(value, float) else str(value)
