"""SAABs: simulated annealing within analysis-by-synthesis, to initialise the face model.

Units: parameters as in `uma.face.geometry` (pixels, radians, unitless action units); costs are
1 - NCC (`uma.fit.cost`); temperatures are in cost units.

Each annealing step proposes `tries` perturbations of the current parameters (Gaussian, step
sizes shrinking with the square root of the temperature, clipped to the search box), evaluates
them together in one batch (the compiled cost is cheapest that way), and takes the best
proposal by the Metropolis rule: always when it lowers the cost, else with probability
exp(-increase / temperature). The best parameters ever seen are returned. The global phase
searches the pose (tx, ty, scale, rx, ry, rz); the local phase then searches the action units
around that pose. The search stops early when the best cost has not improved by `tolerance`
for `patience` steps. Randomness comes only from the generator passed in.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from uma.face.geometry import N_POSE
from uma.fit.cost import Cost
from uma.fit.search import SearchBox

__all__ = ["AnnealingSchedule", "SaabsConfig", "FitResult", "metropolis_accept", "anneal", "saabs"]


@dataclass(frozen=True)
class AnnealingSchedule:
    """One annealing phase: `steps` x `tries` cost evaluations at most."""

    steps: int = 50
    tries: int = 8
    initial_temperature: float = 0.03
    final_temperature: float = 1e-4
    min_step_fraction: float = 0.05  # step sizes never shrink below this share of the initial
    patience: int = 25
    tolerance: float = 1e-5

    def __post_init__(self) -> None:
        if self.steps < 1 or self.tries < 1:
            raise ValueError("an annealing schedule needs at least one step and one try")
        if not 0 < self.final_temperature <= self.initial_temperature:
            raise ValueError("temperatures must satisfy 0 < final <= initial")

    @property
    def cooling(self) -> float:
        """Temperature factor per step, from the initial to the final temperature."""
        if self.steps == 1:
            return 1.0
        return (self.final_temperature / self.initial_temperature) ** (1.0 / (self.steps - 1))

    @property
    def budget(self) -> int:
        return self.steps * self.tries


@dataclass(frozen=True)
class SaabsConfig:
    """SAABs' settings: a global (pose) and a local (action units) phase, both configurable.

    Step sizes are standard deviations at the initial temperature: translations and scale as
    fractions of the face width and scale, angles in radians, action units unitless.
    """

    global_phase: AnnealingSchedule = field(default_factory=AnnealingSchedule)
    local_phase: AnnealingSchedule = field(
        default_factory=lambda: AnnealingSchedule(
            steps=20, tries=5, initial_temperature=0.005, patience=10
        )
    )
    illumination: bool = False
    shift_step: float = 0.06
    scale_step: float = 0.05
    angle_step_rad: float = 0.12
    action_step: float = 0.25
    # The phases score at most this many template pixels (every n-th): at 92x112 the global
    # phase uses every 2nd of ~4,600, at CIF every 9th of ~19,000; the local phase refines.
    global_pixels: int = 2400
    local_pixels: int = 8000
    local_pose_fraction: float = 0.15  # pose step sizes in the local phase, relative


@dataclass(frozen=True, eq=False)
class FitResult:
    """A successful fit: parameters (6 + A,), final cost, how many cost evaluations it took."""

    params: np.ndarray
    cost: float
    evaluations: int
    iterations: int
    history: tuple[float, ...] = ()

    def __bool__(self) -> bool:
        return True


def metropolis_accept(delta: float, temperature: float, uniform: float) -> bool:
    """The Metropolis rule: accept a lower cost always, a higher one with p = exp(-delta / T)."""
    if delta <= 0.0:
        return True
    if temperature <= 0.0:
        return False
    return uniform < np.exp(-delta / temperature)


def anneal(
    cost: Cost,
    start: np.ndarray,
    box: SearchBox,
    step_sizes: np.ndarray,
    schedule: AnnealingSchedule,
    *,
    rng: np.random.Generator,
    active: np.ndarray,
) -> tuple[np.ndarray, float, int, list[float]]:
    """One annealing phase over the `active` parameters; returns (best, its cost, steps, history)."""
    current = box.clip(start)
    current_cost = float(cost(current))
    best, best_cost = current.copy(), current_cost
    history = [best_cost]
    temperature = schedule.initial_temperature
    stale = 0
    step = 0
    mask = active.astype(np.float64)
    for step in range(1, schedule.steps + 1):  # noqa: B007 - reported after the loop
        shrink = max(
            np.sqrt(temperature / schedule.initial_temperature), schedule.min_step_fraction
        )
        noise = rng.standard_normal((schedule.tries, current.size))
        proposals = box.clip(current + noise * (step_sizes * shrink * mask))
        costs = cost(proposals)
        j = int(np.argmin(costs))
        if metropolis_accept(float(costs[j]) - current_cost, temperature, float(rng.random())):
            current, current_cost = proposals[j], float(costs[j])
        if costs[j] < best_cost - schedule.tolerance:
            best, best_cost = proposals[j].copy(), float(costs[j])
            stale = 0
        else:
            stale += 1
        history.append(best_cost)
        if stale >= schedule.patience:
            break
        temperature *= schedule.cooling
    return best, best_cost, step, history


def saabs(
    cost: Cost,
    start: np.ndarray,
    box: SearchBox,
    *,
    config: SaabsConfig = SaabsConfig(),
    rng=None,
    global_cost: Cost | None = None,
    actions: bool = True,
) -> FitResult:
    """Global pose search, then (with `actions`) the action units, from `start` within `box`.

    Each phase scores at most `config.global_pixels` / `config.local_pixels` template pixels
    (`global_cost` replaces the global phase's cost); the returned cost is on the full template.
    """
    rng = np.random.default_rng(rng)
    n_params = start.size
    face_width = box.face_width_px
    steps = np.full(n_params, config.action_step)
    steps[:N_POSE] = [
        config.shift_step * face_width,
        config.shift_step * face_width,
        config.scale_step * start[2],
        config.angle_step_rad,
        config.angle_step_rad,
        config.angle_step_rad * 0.7,
    ]
    pose = np.zeros(n_params, dtype=bool)
    pose[:N_POSE] = True
    first = global_cost if global_cost is not None else _thinned(cost, config.global_pixels)
    before = first.evaluations
    best, _, steps_global, history = anneal(
        first, start, box, steps, config.global_phase, rng=rng, active=pose
    )
    used = first.evaluations - before
    steps_local = 0
    if actions and n_params > N_POSE:
        # The action units move feature points the pose was fitted without: let the pose follow
        # with small steps while the units are searched.
        local_steps = steps.copy()
        local_steps[:N_POSE] *= config.local_pose_fraction
        active = np.ones(n_params, dtype=bool) if config.local_pose_fraction > 0 else ~pose
        local_cost = _thinned(cost, config.local_pixels)
        before = local_cost.evaluations
        best, _, steps_local, more = anneal(
            local_cost, best, box, local_steps, config.local_phase, rng=rng, active=active
        )
        used += local_cost.evaluations - before
        history += more
    best_cost = float(cost(best))
    used += 1
    return FitResult(
        params=best,
        cost=best_cost,
        evaluations=used,
        iterations=steps_global + steps_local,
        history=tuple(history),
    )


def _thinned(cost: Cost, pixels: int) -> Cost:
    """`cost` on every n-th template pixel, so that at most `pixels` remain."""
    step = -(-cost.template.raster.size // max(pixels, 1))
    if step <= 1:
        return cost
    return Cost(cost.template.subsampled(step), cost.image, illumination=cost.illumination)
