"""The receiver's renderer as the codec's profile describes it: one for the bench and the run.

Units: the rings in face-outline and head-ring radii (`uma.mbc.scene_render`).

`uma bench mbc` and the simulation's model codec (`uma.sim.mbc_codecs`) both build the
receiver's `SceneRenderer` here, from the `engine.mbc` section (`uma.config.codecs.MbcConfig`:
its rings and whether the outline is softened as the head moves, `uma.mbc.outline`), so the
bench's figures measure the rendering the simulation runs. The section is read as attributes
(`head_ring_outlines`, `far_ring_head_radii`, `soften_outline`), so this module needs no
configuration code.
"""

from __future__ import annotations

from uma.mbc.scene_render import SceneRenderer

__all__ = ["profile_renderer"]


def profile_renderer(description, size: tuple[int, int], profile, *, layered: bool = True):
    """The receiver's `SceneRenderer` for `description` (a `ContentDescription`) at `size`
    (W, H) as `profile` (the `engine.mbc` section) sizes its rings and softens its outline;
    layered (a plate and a person) or stretched."""
    return SceneRenderer(
        description,
        size,
        head_ring_outlines=profile.head_ring_outlines,
        far_ring_head_radii=profile.far_ring_head_radii,
        soften_outline=profile.soften_outline,
        layered=layered,
    )
