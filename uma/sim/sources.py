"""Open the frame source a scenario names: a video file, raw YUV, or a built-in synthetic one.

Every source yields planar YUV 4:2:0 frames, arrays of shape (H * 3 // 2, W), uint8. A
synthetic source (the pattern, the talking head) is rendered once per process for its settings
and seed (`uma.sim.kept_source`).
"""

from __future__ import annotations

from uma.config.scenario import SourceConfig
from uma.errors import ConfigError

__all__ = ["open_source", "SOURCE_KINDS"]

SOURCE_KINDS = ("pattern", "file", "yuv", "talking-head")


def open_source(config: SourceConfig, *, seed: int):
    """A frame source for `config`; a file source takes its size and rate from the file."""
    if config.kind in ("pattern", "talking-head"):
        from uma.sim.kept_source import KeptSource

        key = f"{config.model_dump_json()} seed {seed}"
        return KeptSource(_open(config, seed=seed), key, lambda: _open(config, seed=seed))
    return _open(config, seed=seed)


def _open(config: SourceConfig, *, seed: int):
    if config.kind == "pattern":
        from uma.video import PatternSource

        return PatternSource(config.width, config.height, config.fps, seed=seed)
    if config.kind == "file":
        from uma.video import VideoFileSource

        return VideoFileSource(config.path, loop=config.loop)
    if config.kind == "yuv":
        from uma.video import RawYuvSource

        return RawYuvSource(config.path, config.width, config.height, config.fps, loop=config.loop)
    if config.kind == "talking-head":
        from uma.face import TalkingHeadSource

        return TalkingHeadSource(
            width=config.width, height=config.height, fps=config.fps, seed=seed
        )
    raise ConfigError(
        f"source.kind: expected one of {', '.join(SOURCE_KINDS)}, got {config.kind!r}"
    )
