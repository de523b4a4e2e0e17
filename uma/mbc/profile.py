"""The receiver's renderer as the codec's profile and the description say: one for the bench and
the simulation, and the head ring the sender chooses for a clip.

Units: the rings in face-outline and head-ring radii (`uma.mbc.scene_render`).

`uma bench mbc` and the simulation's model codec (`uma.sim.mbc_codecs`) both build the
receiver's `SceneRenderer` here, from the `engine.mbc` section (`uma.config.codecs.MbcConfig`,
read as attributes: `head_ring_outlines`, `far_ring_head_radii`, `soften_outline`) and the
content description, so the bench's figures measure the rendering the simulation runs. A
description made from a clip carries the head ring its sender chose on the clip's first second
(`with_sender_ring`: the tight ring where the tracked pose is off at the outline, as on real
faces, the profile's where it is exact); where it carries none the profile's ring is used. With
the tight ring the outline is softened as the head moves (`uma.mbc.outline`) when the profile
says so. docs/mbc.md (session mbc5) has the measurements.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from uma.mbc.scene_render import HEAD_RING_CHOICES, SceneRenderer

__all__ = [
    "profile_renderer",
    "scene_renderer",
    "face_from_description",
    "with_sender_ring",
    "describe_clip_with_ring",
    "RING_FRAMES",
]

RING_FRAMES = 25  # the sender's look at the call's first second before it settles


def profile_renderer(description, size: tuple[int, int], profile, *, layered: bool = True):
    """The receiver's `SceneRenderer` for `description` (a `ContentDescription`) at `size`
    (W, H): its head ring the description's (else `profile`'s, the `engine.mbc` section), the
    outline softened where that ring is tighter than the profile's and `profile` softens;
    layered (a plate and a person) or stretched."""
    chosen = getattr(description, "head_ring_outlines", None)
    ring = profile.head_ring_outlines if chosen is None else chosen
    return SceneRenderer(
        description,
        size,
        head_ring_outlines=ring,
        far_ring_head_radii=profile.far_ring_head_radii,
        soften_outline=bool(profile.soften_outline) and ring < profile.head_ring_outlines,
        layered=layered,
    )


def with_sender_ring(description, pictures: list[np.ndarray], *, seed: int = 0):
    """`description` carrying the head ring of `HEAD_RING_CHOICES` whose rendering from
    `pictures[0]` (YUV 4:2:0, the model tracked on it) best draws the next `RING_FRAMES`
    pictures at their tracked poses (`uma.mbc.light.choose_head_ring`); unchanged (the
    profile's ring) when the face is not tracked on the first picture or on none after it."""
    from uma.mbc.encoder import FaceTracker
    from uma.mbc.light import choose_head_ring

    pictures = list(pictures[: RING_FRAMES + 1])
    if len(pictures) < 2:
        return description
    height = pictures[0].shape[0] * 2 // 3
    tracker = FaceTracker(description, rng=seed)
    results = [tracker.track(picture[:height], frame=i) for i, picture in enumerate(pictures)]
    tracked = [i for i in range(1, len(results)) if results[i]]
    if not results[0] or not tracked:
        return description
    ring = choose_head_ring(description, pictures[0], results[0].params,
                            [pictures[i] for i in tracked], [results[i].params for i in tracked],
                            HEAD_RING_CHOICES)  # fmt: skip
    return replace(description, head_ring_outlines=float(ring))


def describe_clip_with_ring(points_file, *, seed: int = 0):
    """`uma.face.clip.describe_clip(points_file)` carrying the sender's head ring, chosen on the
    points file's video from its frame (a still: none chosen)."""
    from uma.face.clip import describe_clip, load_points
    from uma.face.points import PointsFile
    from uma.video import VideoFileSource

    points = points_file if isinstance(points_file, PointsFile) else load_points(points_file)
    description = describe_clip(points)
    if points.video is None:
        return description
    first = points.frame or 0
    source = VideoFileSource(points.video, max_frames=first + RING_FRAMES + 1)
    return with_sender_ring(description, list(source.frames())[first:], seed=seed)


def scene_renderer(description, size: tuple[int, int], mbc=None, *, layered: bool = True):
    """The receiver's `uma.mbc.SceneRenderer` for `description` at `size`, as the `engine.mbc`
    section `mbc` describes it (`uma.mbc.profile`, as `uma bench mbc` renders; None: the
    section's defaults); layered or stretched."""
    if mbc is None:
        from uma.config.codecs import MbcConfig

        mbc = MbcConfig()
    return profile_renderer(description, size, mbc, layered=layered)


def face_from_description(mbc, frame: int, refresh_frame: int, fps: float) -> bool:
    """Whether the rendered face's own triangles come from the description's texture at
    `frame`, rendering from the refresh of `refresh_frame` (-1: none; the `engine.mbc` section
    `mbc` says where): the refresh picture's face while it is recent (`recent`: within
    `face_recent_ms`; `picture`: always), else the description's (its pose there is exact)."""
    refresh = getattr(mbc, "refresh", None)
    if refresh_frame < 0 or refresh is None or refresh.face == "description":
        return True
    if refresh.face == "picture":
        return False
    return (frame - refresh_frame) * 1000.0 / fps > refresh.face_recent_ms
