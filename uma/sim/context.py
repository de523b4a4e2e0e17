"""What the codecs of one run share: the typed context every encoder and decoder is made with.

Units: sizes in pixels. Pictures are planar YUV 4:2:0 arrays (H * 3 // 2, W) uint8.

`CodecChain` (`uma.sim.codecs`) makes one `CodecContext` per run and hands it to every codec it
builds. The fields a codec reads are fixed when the run starts; `background` (the last picture
the receiver showed before a change of codec: the region and model codecs draw over it) and
`selected` (the selection scheme's parameters sent up by the sender, by source frame) change as
the run goes on, and only the chain writes them.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, fields
from typing import Any

import numpy as np

__all__ = ["CodecContext", "as_context"]


@dataclass
class CodecContext:
    """The run's codec context.

    `description`: the model-based codec's content description (None: the run has none);
    `seed`: the run's seed, for the tracker's random restarts; `source_size`: (width, height)
    of the source; `stream`: the model codec's `uma.mbc.StreamConfig` (None without a
    description); `face_region`: the scenario's `FaceRegionConfig` for the region codec;
    `mbc`: the scenario's `MbcConfig` (light, ring sizes, refresh); `layered`: the model
    codec's receiver draws the layered scene and the engine sends the body motion (False: the
    stretched scene, no body motion; docs/mbc.md "In the simulation" measured both).
    """

    description: Any = None
    seed: int = 0
    source_size: tuple[int, int] = (0, 0)
    stream: Any = None
    face_region: Any = None
    background: np.ndarray | None = None
    selected: dict[int, Any] | None = None
    tracker: Any = None  # a tracker to reuse instead of making one (benchmarks)
    mbc: Any = None  # the scenario's `engine.mbc` section (None: the codec's defaults)
    fps: float = 25.0  # the source's frame rate
    layered: bool = True


def as_context(context: CodecContext | Mapping[str, Any] | None) -> CodecContext:
    """`context` itself, or a mapping of its field names made into one (a codec made outside
    a run, by a benchmark, passes only the fields it needs)."""
    if isinstance(context, CodecContext):
        return context
    known = {f.name for f in fields(CodecContext)}
    given = dict(context or {})
    unknown = sorted(set(given) - known)
    if unknown:
        raise TypeError(
            f"codec context: unknown fields {unknown}; expected some of {sorted(known)}"
        )
    return CodecContext(**given)
