"""Picture quality of a displayed frame against its source: PSNR and SSIM of 8-bit planes.

Pass luma planes (`frame[:H]` of a YUV 4:2:0 frame), as is usual for video quality. Units: PSNR
in dB for a peak of 255, capped at `PSNR_CAP_DB` (100 dB) for identical pictures so a mean stays
finite; SSIM unitless in [-1, 1]; `ssim_db` = -10 log10(1 - SSIM), the form real-time video work
reports (Salsify), capped at `SSIM_DB_CAP` (100 dB).

SSIM is scikit-image's `structural_similarity` with its defaults (7x7 uniform window, K1 0.01,
K2 0.03, sample covariance N/(N-1), the map's (7-1)//2-pixel border left out of the mean), data
range 255. On uint8 planes the window sums are exact integers and the covariances are formed
in integers before one float32 division (one compiled pass without the GIL,
`uma.metrics.ssim_kernel`), so the value agrees with scikit-image's float64 computation to about
1e-7; other dtypes go through OpenCV's float64 filters. The map goes into a per-thread buffer
reused across calls (same shape), so the cost does not depend on how malloc serves large
temporaries.

`frame_scores` scores a frame and its face box in one pass: the box's SSIM is the mean of the
frame's SSIM map over the box shrunk by the window's 3-pixel border, which equals, value for
value, scikit-image's SSIM of the box cropped out of both planes (every window it averages lies
inside the crop), so `region_scores` and `frame_scores` agree exactly.

`scale=2` averages 2x2 blocks of both planes first (a quarter of the pixels). It hides coding
artefacts smaller than the blocks and reads higher (akiyo CIF coded at 64 to 768 kbit/s: +2.6
to +5.4 dB in `ssim_db`). Rankings hold but values do not compare with published full-size SSIM;
compare only values computed at the same scale. (Wang et al.'s own recipe downsamples by
round(min(H, W) / 256), which is 1, no downsampling, for CIF and QCIF.)
"""

from __future__ import annotations

import math
import threading
from collections import OrderedDict

import numpy as np

__all__ = [
    "psnr_db",
    "ssim",
    "ssim_db",
    "region_scores",
    "frame_scores",
    "keep_freed_memory",
    "PSNR_CAP_DB",
    "SSIM_DB_CAP",
]

PSNR_CAP_DB = 100.0
SSIM_DB_CAP = 100.0


def _same_shape(reference: np.ndarray, test: np.ndarray, what: str) -> None:
    if reference.shape != test.shape:
        raise ValueError(f"{what} of different shapes {reference.shape} and {test.shape}")
    if reference.size == 0:
        raise ValueError(f"{what} of empty planes")


def psnr_db(reference: np.ndarray, test: np.ndarray) -> float:
    """Peak signal-to-noise ratio of two 8-bit planes, 10 log10(255^2 / MSE), in dB."""
    _same_shape(reference, test, "PSNR")
    return _psnr_of_mse(_mse(reference, test))


def _mse(reference: np.ndarray, test: np.ndarray) -> float:
    if reference.dtype == np.uint8 and test.dtype == np.uint8:
        import cv2

        # OpenCV sums the squared differences of uint8 planes exactly (integers)
        return cv2.norm(reference, test, cv2.NORM_L2SQR) / reference.size
    diff = reference.astype(np.float64) - test.astype(np.float64)
    return float(np.mean(diff * diff))


def _psnr_of_mse(mse: float) -> float:
    if mse <= 255.0**2 * 10 ** (-PSNR_CAP_DB / 10):
        return PSNR_CAP_DB
    return float(10.0 * np.log10(255.0**2 / mse))


def _downscale(plane: np.ndarray, scale: int) -> np.ndarray:
    import cv2

    height, width = plane.shape[0] // scale, plane.shape[1] // scale
    cropped = plane[: height * scale, : width * scale]
    # INTER_AREA at an integer factor is the exact mean of each scale x scale block
    return cv2.resize(cropped, (width, height), interpolation=cv2.INTER_AREA)


_WINDOW = 7  # scikit-image's default uniform window
_BORDER = (_WINDOW - 1) // 2  # the map's border scikit-image leaves out of its mean
_N = _WINDOW * _WINDOW
_C1 = (0.01 * 255.0) ** 2
_C2 = (0.03 * 255.0) ** 2
_buffers = threading.local()
_SHAPES_KEPT = 4  # per thread: a frame size and a few crop sizes; older shapes are dropped


def _buffer(name: str, shape: tuple[int, int], dtype) -> np.ndarray:
    """A per-thread array reused across calls of the same shape: no page faults per frame.

    Only the `_SHAPES_KEPT` shapes used last keep their arrays, so scoring crops of ever new
    sizes (face boxes) does not pile up memory.
    """
    shapes = getattr(_buffers, "shapes", None)
    if shapes is None:
        shapes = _buffers.shapes = OrderedDict()
    arrays = shapes.get(shape)
    if arrays is None:
        if len(shapes) >= _SHAPES_KEPT:
            shapes.popitem(last=False)
        arrays = shapes[shape] = {}
    else:
        shapes.move_to_end(shape)
    key = (name, np.dtype(dtype).str)
    array = arrays.get(key)
    if array is None:
        array = arrays[key] = np.empty(shape, dtype)
    return array


def _ssim_map_uint8(ref: np.ndarray, tst: np.ndarray) -> np.ndarray:
    """The SSIM map of two uint8 planes, exact window sums; valid inside the `_BORDER` frame
    only (the rest is not written). With S the window sums, the map is
    (2 SxSy + C1 N^2)(2 (N Sxy - SxSy) + C2 N(N-1)) / ((Sx^2 + Sy^2 + C1 N^2)(N (Sxx + Syy) -
    Sx^2 - Sy^2 + C2 N(N-1))), scikit-image's formula multiplied through by N^3 (N-1), each
    factor rounded once from its exact integer (`uma.metrics.ssim_kernel`, one compiled pass
    without the GIL). Returns a per-thread buffer, overwritten by the next call.
    """
    from uma.metrics.ssim_kernel import ssim_map_inside

    out = _buffer("f0", ref.shape, np.float32)
    return ssim_map_inside(ref, tst, _WINDOW, _C1 * _N * _N, _C2 * _N * (_N - 1), out)


def _ssim_map_float(ref: np.ndarray, tst: np.ndarray) -> np.ndarray:
    """The SSIM map of two planes of any dtype, float64 filters; scikit-image's formula as is."""
    import cv2

    def mean(plane: np.ndarray) -> np.ndarray:
        return cv2.blur(plane, (_WINDOW, _WINDOW), borderType=cv2.BORDER_REFLECT)

    x, y = ref.astype(np.float64), tst.astype(np.float64)
    ux, uy = mean(x), mean(y)
    norm = _N / (_N - 1)
    vx = norm * (mean(x * x) - ux * ux)
    vy = norm * (mean(y * y) - uy * uy)
    vxy = norm * (mean(x * y) - ux * uy)
    return ((2 * ux * uy + _C1) * (2 * vxy + _C2)) / ((ux * ux + uy * uy + _C1) * (vx + vy + _C2))


def _ssim_map(ref: np.ndarray, tst: np.ndarray) -> np.ndarray:
    if ref.dtype == np.uint8 and tst.dtype == np.uint8:
        return _ssim_map_uint8(np.ascontiguousarray(ref), np.ascontiguousarray(tst))
    return _ssim_map_float(ref, tst)


def _map_mean(similarity: np.ndarray, y0: int, y1: int, x0: int, x1: int) -> float:
    """Mean of the map over rows y0:y1, columns x0:x1 less the window's border."""
    inner = similarity[y0 + _BORDER : y1 - _BORDER, x0 + _BORDER : x1 - _BORDER]
    return float(inner.mean(dtype=np.float64))


def ssim(reference: np.ndarray, test: np.ndarray, *, scale: int = 1) -> float:
    """Mean structural similarity of two 8-bit planes (scikit-image's definition, data range 255).

    `scale` > 1 averages `scale` x `scale` blocks of both planes first: about `scale`^2 times
    cheaper, and higher than full-size SSIM (see the module notes). Planes must be at least
    7 x 7 after scaling.
    """
    _same_shape(reference, test, "SSIM")
    if int(scale) != scale or scale < 1:
        raise ValueError(f"SSIM scale: expected a positive integer, got {scale!r}")
    ref, tst = reference, test
    if scale > 1:
        ref = _downscale(ref.astype(np.float32), int(scale))
        tst = _downscale(tst.astype(np.float32), int(scale))
    if min(ref.shape) < _WINDOW:
        raise ValueError(f"SSIM needs planes of at least 7x7, got {ref.shape} at scale {scale}")
    height, width = ref.shape
    return _map_mean(_ssim_map(ref, tst), 0, height, 0, width)


def _clip_box(box, shape: tuple[int, int]) -> tuple[int, int, int, int] | None:
    """(y0, y1, x0, x1) of `box` clipped to a plane of `shape`; None when nothing is left."""
    x0, y0 = max(0, int(box.x)), max(0, int(box.y))
    x1 = min(shape[1], int(box.x) + int(box.width))
    y1 = min(shape[0], int(box.y) + int(box.height))
    if x1 <= x0 or y1 <= y0:
        return None
    return y0, y1, x0, x1


def region_scores(
    reference: np.ndarray, test: np.ndarray, box, *, with_psnr: bool = True, with_ssim: bool = True
) -> tuple[float, float]:
    """(PSNR dB, SSIM) of two planes over `box` only (x, y, width, height, clipped to the plane).

    NaN for a metric switched off, without a box, and SSIM NaN for a box under 7x7 pixels.
    """
    nan = float("nan")
    if box is None:
        return nan, nan
    _same_shape(reference, test, "face-region scores")
    clipped = _clip_box(box, reference.shape)
    if clipped is None:
        return nan, nan
    y0, y1, x0, x1 = clipped
    ref, tst = reference[y0:y1, x0:x1], test[y0:y1, x0:x1]
    face_psnr = psnr_db(ref, tst) if with_psnr else nan
    face_ssim = ssim(ref, tst) if with_ssim and min(ref.shape) >= _WINDOW else nan
    return face_psnr, face_ssim


def frame_scores(
    reference: np.ndarray,
    test: np.ndarray,
    box=None,
    *,
    with_psnr: bool = True,
    with_ssim: bool = True,
) -> tuple[float, float, float, float]:
    """(PSNR dB, SSIM, face PSNR dB, face SSIM) of two planes: whole frame and over `box`.

    One SSIM map serves both the frame and the box, with the same values as `psnr_db`, `ssim`
    and `region_scores` (see the module notes). NaN for a
    metric switched off; face scores NaN as `region_scores` gives them. Planes at least 7x7.
    """
    nan = float("nan")
    _same_shape(reference, test, "frame scores")
    clipped = None if box is None else _clip_box(box, reference.shape)
    psnr = face_psnr = similarity = face_ssim = nan
    if with_psnr:
        psnr = _psnr_of_mse(_mse(reference, test))
        if clipped is not None:
            y0, y1, x0, x1 = clipped
            face_psnr = _psnr_of_mse(_mse(reference[y0:y1, x0:x1], test[y0:y1, x0:x1]))
    if with_ssim:
        if min(reference.shape) < _WINDOW:
            raise ValueError(f"SSIM needs planes of at least 7x7, got {reference.shape}")
        height, width = reference.shape
        similarity_map = _ssim_map(reference, test)
        similarity = _map_mean(similarity_map, 0, height, 0, width)
        if clipped is not None and min(clipped[1] - clipped[0], clipped[3] - clipped[2]) >= _WINDOW:
            face_ssim = _map_mean(similarity_map, *clipped)
    return psnr, similarity, face_psnr, face_ssim


def ssim_db(similarity: float) -> float:
    """SSIM in dB, -10 log10(1 - SSIM), capped at `SSIM_DB_CAP`; NaN stays NaN."""
    if math.isnan(similarity):
        return math.nan
    if similarity >= 1.0 - 10 ** (-SSIM_DB_CAP / 10):
        return SSIM_DB_CAP
    return -10.0 * math.log10(1.0 - similarity)


def keep_freed_memory(*, mmap_threshold_bytes: int = 64 << 20, trim_bytes: int = 256 << 20) -> bool:
    """Make glibc's malloc keep and reuse freed memory for large arrays, for this whole process.

    Sets M_MMAP_THRESHOLD (allocations below it come from the heap, not a fresh mmap) and
    M_TRIM_THRESHOLD (free memory kept at the heap's top before it is returned to the system).
    Call once at the start of a run or benchmark; it changes speed, never results. The heap
    may then hold up to `trim_bytes` more than it uses. Returns False where the C library is
    not glibc (nothing is changed).
    """
    import ctypes
    import ctypes.util

    name = ctypes.util.find_library("c")
    try:
        libc = ctypes.CDLL(name or "libc.so.6")
        mallopt = libc.mallopt
    except (OSError, AttributeError):
        return False
    m_trim_threshold, m_mmap_threshold = -1, -3  # from glibc's malloc.h
    return bool(mallopt(m_mmap_threshold, mmap_threshold_bytes)) and bool(
        mallopt(m_trim_threshold, trim_bytes)
    )
