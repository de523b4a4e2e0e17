"""Argument types shared by the sub-commands (standard library only)."""

from __future__ import annotations

import argparse

__all__ = ["frame_size"]

NAMED_SIZES = {"cif": (352, 288), "qcif": (176, 144)}


def frame_size(text: str) -> tuple[int, int]:
    """`cif`, `qcif` or `WxH` with even sides of at least 16 pixels."""
    if text.lower() in NAMED_SIZES:
        return NAMED_SIZES[text.lower()]
    try:
        width, height = (int(v) for v in text.lower().split("x"))
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected cif, qcif or WxH, got {text!r}") from None
    if width < 16 or height < 16 or width % 2 or height % 2:
        raise argparse.ArgumentTypeError(f"expected even sides of at least 16 pixels, got {text!r}")
    return width, height
