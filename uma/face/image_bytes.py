"""Bytes that may be a picture: what they look like, and decoding them without OpenCV's log.

OpenCV writes its own lines to stderr when a PNG or JPEG is damaged (`[ERROR:0@0.2] ...
readHeader ...`); the command line promises one line, its own, so decoding here silences that
log and callers say what failed.
"""

from __future__ import annotations

import numpy as np

__all__ = ["what_the_bytes_look_like", "decode_image"]

_SIGNATURES = (
    (b"\xff\xd8\xff", "a JPEG image"),
    (b"\x89PNG\r\n\x1a\n", "a PNG image"),
    (b"GIF8", "a GIF image"),
    (b"BM", "a BMP image"),
    (b"\x93NUMPY", "a single .npy array"),
    (b"\x1f\x8b", "a gzip file"),
    (b"%PDF", "a PDF document"),
    (b"P5", "a PGM image"),
    (b"<?xml", "an XML file"),
)


def what_the_bytes_look_like(data: bytes) -> str:
    """A few words on what `data` seems to be, for 'expected X, got Y' messages."""
    if not data:
        return "an empty file"
    if data[4:8] == b"ftyp":
        return "an MP4/MOV video"
    for signature, name in _SIGNATURES:
        if data.startswith(signature):
            return name
    head = data[:512]
    try:
        text = head.decode("utf-8")
    except UnicodeDecodeError:
        return f"{len(data)} bytes of binary data"
    first = text.strip().splitlines()[0][:40] if text.strip() else ""
    return f"text ({first!r} ...)" if first else "blank text"


def decode_image(data: np.ndarray, flags: int | None = None) -> np.ndarray | None:
    """`cv2.imdecode(data, flags)` (default `IMREAD_COLOR`) with OpenCV's log silenced; None
    when the bytes are no picture OpenCV can decode."""
    import cv2

    flags = cv2.IMREAD_COLOR if flags is None else flags
    log = getattr(getattr(cv2, "utils", None), "logging", None)
    if log is None:
        return cv2.imdecode(data, flags)
    level = log.getLogLevel()
    log.setLogLevel(log.LOG_LEVEL_SILENT)
    try:
        return cv2.imdecode(data, flags)
    finally:
        log.setLogLevel(level)
