"""SAABs: simulated annealing within analysis-by-synthesis, to initialise the face model.

Units: parameters as in `uma.face.geometry` (pixels, radians, unitless action units); costs are
1 - correlation (`uma.fit.cost`); temperatures are in cost units; step sizes are the RMS motion
of the model's projected points per proposal, as a fraction of the face width
(`uma.fit.perturb`).

Each annealing step proposes `tries` perturbations of the current parameters (the perturbation
function draws them; step sizes shrink with the square root of the temperature, down to a
floor; proposals are clipped to the search box), evaluates them together in one batch (the
compiled cost is cheapest that way) and takes the best proposal by the Metropolis rule: always
when it lowers the cost, else with probability exp(-increase / temperature). The temperature
falls geometrically from the initial to the final one. The best parameters ever seen are
returned. The global phase searches the pose (tx, ty, scale, rx, ry, rz) on a subset of the
template's pixels, in stages (`Stage`) on images blurred less and less as it cools (coarse to
fine: a wide basin first, precision last), each stage with its own view of the images (blurred,
or band-passed log intensity) and its own illumination setting if it names one; the local
phase then searches the action units together with the pose, on all pixels. A phase may stop early when its best cost has not improved by
`tolerance` for `patience` steps. Randomness comes only from the generator passed in; wall-clock
time never enters.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace

import numpy as np

from uma.face.geometry import N_POSE
from uma.fit.cost import Cost
from uma.fit.perturb import PERTURBATIONS, Perturbation
from uma.fit.result import FitResult
from uma.fit.search import SearchBox

__all__ = [
    "Stage",
    "AnnealingSchedule",
    "SaabsConfig",
    "FitResult",
    "PhaseResult",
    "metropolis_accept",
    "anneal",
    "saabs",
]


@dataclass(frozen=True)
class AnnealingSchedule:
    """One annealing phase: at most `steps` x `tries` cost evaluations."""

    steps: int = 38
    tries: int = 8
    initial_temperature: float = 0.03
    final_temperature: float = 1e-4
    initial_step: float = 0.05  # RMS point motion per proposal / face width, at the start
    min_step_fraction: float = 0.01  # steps never shrink below this share of the initial
    patience: int = 0  # steps without improvement before stopping (0: run every step)
    tolerance: float = 1e-6  # an improvement smaller than this does not count

    def __post_init__(self) -> None:
        if self.steps < 1 or self.tries < 1:
            raise ValueError(
                f"annealing schedule: steps and tries must be >= 1, got {self.steps} and {self.tries}"
            )
        if not 0 < self.final_temperature <= self.initial_temperature < math.inf:
            raise ValueError(
                "annealing schedule: temperatures must satisfy 0 < final <= initial, got "
                f"{self.final_temperature} and {self.initial_temperature}"
            )
        if not 0 < self.initial_step < math.inf or not 0 < self.min_step_fraction <= 1:
            raise ValueError(
                f"annealing schedule: initial_step must be > 0 and min_step_fraction in (0, 1], "
                f"got {self.initial_step} and {self.min_step_fraction}"
            )
        if self.patience < 0 or not self.tolerance >= 0:
            raise ValueError("annealing schedule: patience and tolerance must be >= 0")

    @property
    def cooling(self) -> float:
        """Temperature factor per step, from the initial to the final temperature."""
        if self.steps == 1:
            return 1.0
        return (self.final_temperature / self.initial_temperature) ** (1.0 / (self.steps - 1))

    @property
    def budget(self) -> int:
        return self.steps * self.tries

    def step_scale(self, temperature: float) -> float:
        """Step size relative to the initial one at `temperature`."""
        return max(math.sqrt(temperature / self.initial_temperature), self.min_step_fraction)


@dataclass(frozen=True)
class Stage:
    """How one stage of the global phase looks at the images (sizes as fractions of the face
    width): blurred by a Gaussian of `blur`, or with `band` > `blur` the band-pass of the log
    intensity between the two (`uma.fit.cost.prepared`); `illumination` overrides the cost's
    own setting (None keeps it)."""

    blur: float
    band: float = 0.0
    illumination: float | None = None

    def __post_init__(self) -> None:
        if not 0 <= self.blur < 1 or not (self.band == 0 or self.blur < self.band < 1):
            raise ValueError(
                f"SAABs stage: expected 0 <= blur < 1 and band 0 or in (blur, 1), got "
                f"blur {self.blur}, band {self.band}"
            )
        if self.illumination is not None and not 0 <= self.illumination <= 1:
            raise ValueError(
                f"SAABs stage: illumination must be None or in [0, 1], got {self.illumination}"
            )


@dataclass(frozen=True)
class SaabsConfig:
    """SAABs' settings: a global (pose) and a local (pose and action units) phase.

    The defaults spend 304 + 200 evaluations: measured on `uma bench init`, giving the action
    units 200 rather than the paper's 100 halves SAABs' median error for the same total.
    """

    global_phase: AnnealingSchedule = field(default_factory=AnnealingSchedule)
    local_phase: AnnealingSchedule = field(
        default_factory=lambda: AnnealingSchedule(
            steps=40,
            tries=5,
            initial_temperature=0.005,
            final_temperature=5e-4,
            initial_step=0.004,
        )
    )
    illumination: bool | float = False  # per-patch compensation, or its weight (uma.fit.cost)
    perturbation: str = "metric"  # or "axes" (see uma.fit.perturb)
    # The global phase runs in equal stages, coarse to fine as it cools: here on images blurred
    # by Gaussians of these fractions of the face width (4 px, then 1 px on a 78-px face).
    global_stages: tuple[Stage, ...] = (Stage(0.05), Stage(0.0125))
    global_pixels: int = 2400  # the global phase scores at most this many template pixels
    local_pixels: int = 8000

    def __post_init__(self) -> None:
        if self.perturbation not in PERTURBATIONS:
            raise ValueError(
                f"SAABs perturbation: expected one of {PERTURBATIONS}, got {self.perturbation!r}"
            )
        count = len(self.global_stages)
        if not 1 <= count <= self.global_phase.steps:
            raise ValueError(
                f"SAABs global_stages: expected 1 to {self.global_phase.steps} stages, got {count}"
            )
        if self.global_pixels < 16 or self.local_pixels < 16:
            raise ValueError("SAABs global_pixels and local_pixels must be >= 16")

    @property
    def budget(self) -> int:
        """Cost evaluations at most: both phases, the start of each stage, the final scoring."""
        return self.global_phase.budget + self.local_phase.budget + len(self.global_stages) + 2


def stages(schedule: AnnealingSchedule, count: int) -> list[AnnealingSchedule]:
    """`schedule` cut into `count` consecutive schedules that together cool as it does."""
    if count <= 1:
        return [schedule]
    bounds = np.linspace(0, schedule.steps, count + 1).round().astype(int)
    out = []
    for first, end in zip(bounds[:-1], bounds[1:], strict=True):
        t_first = schedule.initial_temperature * schedule.cooling**first
        t_last = schedule.initial_temperature * schedule.cooling ** (end - 1)
        scale = schedule.step_scale(t_first)
        out.append(
            replace(
                schedule,
                steps=int(end - first),
                initial_temperature=float(t_first),
                final_temperature=float(min(t_last, t_first)),
                initial_step=float(schedule.initial_step * scale),
                min_step_fraction=min(1.0, schedule.min_step_fraction / scale),
            )
        )
    return out


@dataclass(frozen=True, eq=False)
class PhaseResult:
    params: np.ndarray
    cost: float
    steps: int
    evaluations: int
    history: tuple[float, ...]


def metropolis_accept(delta: float, temperature: float, uniform: float) -> bool:
    """The Metropolis rule: accept a lower cost always, a higher one with p = exp(-delta / T)."""
    if delta <= 0.0:
        return True
    if temperature <= 0.0 or not math.isfinite(delta):
        return False
    return uniform < math.exp(-delta / temperature)


def anneal(
    cost: Cost,
    start: np.ndarray,
    box: SearchBox,
    schedule: AnnealingSchedule,
    perturbation: Perturbation,
    *,
    rng: np.random.Generator,
    face_width_px: float,
) -> PhaseResult:
    """One annealing phase from `start`; the best parameters seen and their cost."""
    before = cost.evaluations
    current = box.clip(np.asarray(start, dtype=np.float64))
    current_cost = float(cost(current))
    best, best_cost = current.copy(), current_cost
    history = [best_cost]
    temperature = schedule.initial_temperature
    first_step_px = schedule.initial_step * face_width_px
    stale = 0
    step = 0
    for step in range(1, schedule.steps + 1):  # noqa: B007 - reported after the loop
        step_px = first_step_px * schedule.step_scale(temperature)
        proposals = box.clip(perturbation(rng, current, schedule.tries, step_px))
        costs = cost(proposals)
        j = int(costs.argmin())
        if metropolis_accept(float(costs[j]) - current_cost, temperature, float(rng.random())):
            current, current_cost = proposals[j], float(costs[j])
        if costs[j] < best_cost - schedule.tolerance:
            best, best_cost = proposals[j].copy(), float(costs[j])
            stale = 0
        else:
            stale += 1
            if costs[j] < best_cost:
                best, best_cost = proposals[j].copy(), float(costs[j])
        history.append(best_cost)
        if schedule.patience and stale >= schedule.patience:
            break
        temperature *= schedule.cooling
    return PhaseResult(best, best_cost, step, cost.evaluations - before, tuple(history))


def saabs(
    cost: Cost,
    start: np.ndarray,
    box: SearchBox,
    *,
    config: SaabsConfig = SaabsConfig(),
    rng=None,
    actions: bool = True,
    history: bool = False,
) -> FitResult:
    """Global pose search, then (with `actions`) the action units with the pose, from `start`
    within `box`. `cost` is the full-resolution cost (its `illumination` setting is used by
    both phases); the returned cost is on it."""
    rng = np.random.default_rng(rng)
    model = cost.template.model
    start = box.clip(np.asarray(start, dtype=np.float64))
    width = box.face_width_px
    pose = np.zeros(start.size, dtype=bool)
    pose[:N_POSE] = True
    best, used, steps, trace = start, 0, 0, ()
    template_width = cost.template.face_width_px
    parts = stages(config.global_phase, len(config.global_stages))
    for schedule, stage in zip(parts, config.global_stages, strict=True):
        illumination = cost.illumination if stage.illumination is None else stage.illumination
        coarse = Cost(
            cost.template,
            cost.image,
            illumination=illumination,
            blur_px=stage.blur * width,
            band_px=stage.band * width,
            # The same filter relative to the template's own face (and the same on every frame).
            template_px=(stage.blur * template_width, stage.band * template_width),
        ).thinned(config.global_pixels)
        moves = Perturbation.build(model, best, pose, kind=config.perturbation)
        found = anneal(coarse, best, box, schedule, moves, rng=rng, face_width_px=width)
        best = found.params
        used += found.evaluations
        steps += found.steps
        trace += found.history
    if actions and start.size > N_POSE:
        fine = cost.thinned(config.local_pixels)
        everything = np.ones(start.size, dtype=bool)
        moves = Perturbation.build(model, best, everything, kind=config.perturbation)
        refined = anneal(fine, best, box, config.local_phase, moves, rng=rng, face_width_px=width)
        best = refined.params
        used += refined.evaluations
        steps += refined.steps
        trace += refined.history
    final = float(cost(best))
    return FitResult(
        params=best,
        cost=final,
        evaluations=used + 1,
        iterations=steps,
        history=trace if history else (),
    )
