"""The SimPy world: sender, links, engine and receiver processes, wired by `run_scenario`.

Only this package imports SimPy; `capacity` is pure and usable alone.
"""

from uma.sim.capacity import CapacitySchedule
from uma.sim.world import RunResult, build_capacity, run_scenario

__all__ = ["CapacitySchedule", "RunResult", "run_scenario", "build_capacity"]
