"""Fitting the face model to an image: the cost, SAABs, Gauss-Newton, the hybrid, MDE.

Pure numpy and compiled kernels (numba); no SimPy. Fits return a `FitResult` or a
`uma.failure.Failure` that tests false and says why.
"""

from uma.fit.cost import Cost, FitTemplate
from uma.fit.fit import fit_face, initial_guess
from uma.fit.gauss_newton import GaussNewtonConfig, gauss_newton
from uma.fit.hybrid import HybridConfig, hybrid
from uma.fit.mde import mde_px
from uma.fit.perturb import Perturbation, point_metric
from uma.fit.result import FitResult
from uma.fit.saabs import (
    AnnealingSchedule,
    SaabsConfig,
    Stage,
    anneal,
    metropolis_accept,
    saabs,
)
from uma.fit.search import SearchBox, search_box

__all__ = [
    "FitTemplate",
    "Cost",
    "AnnealingSchedule",
    "SaabsConfig",
    "Stage",
    "HybridConfig",
    "hybrid",
    "FitResult",
    "metropolis_accept",
    "Perturbation",
    "point_metric",
    "anneal",
    "saabs",
    "GaussNewtonConfig",
    "gauss_newton",
    "SearchBox",
    "search_box",
    "mde_px",
    "fit_face",
    "initial_guess",
]
