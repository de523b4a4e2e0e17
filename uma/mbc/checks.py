"""Whether a content description can drive the codec: a model the codec can measure, a
pose that places it, a texture it can render."""

from __future__ import annotations

import numpy as np

from uma.errors import FaceError
from uma.face.describe import ContentDescription
from uma.face.geometry import N_POSE

__all__ = ["check_description", "EDGE_REACH_OF_SCALE"]

EDGE_REACH_OF_SCALE = 0.25  # how far past its texture the model may reach, in its scale_px


def check_description(description: ContentDescription, *, where: str = "description") -> None:
    """Raise `FaceError` naming `where` when the description does not match its model."""
    from uma.mbc.units import FaceUnits

    model = description.model
    params = np.asarray(description.params, dtype=np.float64)
    if params.shape != (N_POSE + model.n_actions,):
        raise FaceError(
            f"{where}: the pose has {params.size} parameters, the model "
            f"{N_POSE + model.n_actions} (6 pose + {model.n_actions} action units)"
        )
    if not np.all(np.isfinite(params)) or not params[2] > 0:
        raise FaceError(
            f"{where}: params: expected a finite pose with a positive scale_px, got "
            f"{[round(float(v), 3) for v in params[:6]]}"
        )
    texture = description.texture
    if texture is None or texture.ndim not in (2, 3) or min(texture.shape[:2]) < 16:
        raise FaceError(f"{where}: the texture is missing or smaller than 16x16")
    points = description.projected()
    # A face cut by the picture's edge (foreman's forehead above the picture: 86 % of the
    # vertices inside) reaches past its texture by less than a quarter of its scale; a model
    # that does not match its texture lies much further out (docs/mbc.md, session mbc5).
    reach = EDGE_REACH_OF_SCALE * float(params[2])
    inside = (
        (points[:, 0] >= -1 - reach)
        & (points[:, 0] <= texture.shape[1] + reach)
        & (points[:, 1] >= -1 - reach)
        & (points[:, 1] <= texture.shape[0] + reach)
    )
    if inside.mean() < 0.9:
        raise FaceError(
            f"{where}: the model lies outside its texture ({100 * inside.mean():.0f} % of "
            f"vertices within {reach:.1f} px of it): description and model do not match"
        )
    try:
        FaceUnits.of(model, params)
    except FaceError as err:
        raise FaceError(f"{where}: {err}") from None
