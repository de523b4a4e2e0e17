"""Texture mapping with the wireframe: rasterise once, warp and sample many times.

Units: pixels (x right, y down, pixel centres at integer coordinates).

`rasterize` finds, for every pixel centre inside the projected mesh, its triangle and
barycentric coordinates: done once per template. `warp_points` moves those pixels with the
vertices (for many parameter sets at once) and `sample_bilinear` reads an image there: the
inverse mapping that fitting calls thousands of times. `render` is the forward direction: it
rasterises the target and maps each target pixel back into the texture.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

__all__ = [
    "Raster",
    "RenderResult",
    "triangle_labels",
    "barycentric_affine",
    "rasterize",
    "warp_points",
    "sample_bilinear",
    "render",
]

_BATCH_MIN = 4  # point sets from which warping goes through one matrix product
_REMAP_MAX = 32767  # cv2.remap's widest map
_REMAP_COLS = 4096


@dataclass(frozen=True, eq=False)
class Raster:
    """Pixels covered by a projected mesh; `corners` are the vertex numbers of each pixel's triangle."""

    ys: np.ndarray  # (K,) int
    xs: np.ndarray  # (K,) int
    tri: np.ndarray  # (K,) int
    bary: np.ndarray  # (K, 3) float32
    corners: np.ndarray  # (K, 3) int
    shape: tuple[int, int]
    inside: np.ndarray | None = None  # (K,) bool: centre inside its triangle (not clamped onto it)

    @property
    def size(self) -> int:
        return int(self.ys.shape[0])

    def weights(self, n_vertices: int):
        """Barycentric weights as a sparse (K, N) float32 CSR matrix: warped = weights @ points.

        Built on first use for each vertex count and kept (the raster is immutable).
        """
        cache = self.__dict__.setdefault("_weights", {})
        if n_vertices not in cache:
            from scipy.sparse import csr_matrix

            if self.size and int(self.corners.max()) >= n_vertices:
                raise ValueError(
                    f"raster names vertex {int(self.corners.max())}, points have {n_vertices}"
                )
            rows = np.repeat(np.arange(self.size), 3)
            cache[n_vertices] = csr_matrix(
                (self.bary.ravel(), (rows, self.corners.ravel())),
                shape=(self.size, n_vertices),
                dtype=np.float32,
            )
        return cache[n_vertices]

    def take(self, keep: np.ndarray) -> Raster:
        """The pixels selected by `keep` (a boolean mask or indices)."""
        inside = None if self.inside is None else self.inside[keep]
        return Raster(
            ys=self.ys[keep],
            xs=self.xs[keep],
            tri=self.tri[keep],
            bary=self.bary[keep],
            corners=self.corners[keep],
            shape=self.shape,
            inside=inside,
        )


@dataclass(frozen=True, eq=False)
class RenderResult:
    image: np.ndarray
    mask: np.ndarray  # bool (H, W): pixels the face covers


def barycentric_affine(points_px: np.ndarray, triangles: np.ndarray) -> np.ndarray:
    """(T, 3, 3): row j of triangle t gives its j-th barycentric coordinate as c . (x, y, 1).

    A vertex value v (N, C) interpolates over triangle t as `(A[t].T @ v[triangles[t]]).T`, an
    affine function of the pixel position; degenerate triangles get finite, meaningless rows.
    """
    from uma.face.raster_kernels import barycentric_rows

    points = np.asarray(points_px, dtype=np.float64)
    out = np.empty((len(triangles), 3, 3), np.float64)
    # Compiled: per triangle, l1 = ((p - a) x v1) / det and l2 = (v0 x (p - a)) / det as
    # c_x x + c_y y + c_0 (v0 = b - a, v1 = c - a), and l0 = 1 - l1 - l2.
    barycentric_rows(points, np.asarray(triangles), out)
    return out


def _barycentric(
    points: np.ndarray, triangles: np.ndarray, tri: np.ndarray, px: np.ndarray
) -> np.ndarray:
    """Barycentric coordinates of pixels `px` (K, 2) in their triangles `tri` (K,): one gather
    of per-triangle coefficients and a dot product each."""
    coeffs = barycentric_affine(points, triangles)[tri]  # (K, 3, 3)
    return coeffs[..., 0] * px[:, 0, None] + coeffs[..., 1] * px[:, 1, None] + coeffs[..., 2]


def triangle_labels(
    points_px: np.ndarray,
    triangles: np.ndarray,
    shape: tuple[int, int],
    *,
    triangle_mask: np.ndarray | None = None,
    depth: np.ndarray | None = None,
) -> np.ndarray:
    """(H, W) int32: the triangle drawn at each pixel centre, -1 where none (see `rasterize`)."""
    import cv2

    points = np.asarray(points_px, dtype=np.float64)
    labels = np.full(shape, -1, dtype=np.int32)
    order = np.arange(len(triangles))
    if triangle_mask is not None:
        order = order[np.asarray(triangle_mask, bool)]
    if depth is not None:
        order = order[np.argsort(np.asarray(depth)[triangles[order]].mean(axis=1), kind="stable")]
    # Fill each triangle's pixel centres as fillPoly does, at 4 bits of sub-pixel precision:
    # compiled, except a triangle reaching outside the picture (OpenCV clips it).
    from uma.face.raster_kernels import fill_triangles

    polygons = np.round(points[triangles] * 16).astype(np.int32)
    order = np.ascontiguousarray(order, dtype=np.int64)
    done = 0
    while done < len(order):
        done = fill_triangles(labels, polygons, order, done)
        if done < len(order):
            t = int(order[done])
            cv2.fillPoly(labels, [polygons[t]], t, lineType=cv2.LINE_8, shift=4)
            done += 1
    return labels


def rasterize(
    points_px: np.ndarray,
    triangles: np.ndarray,
    shape: tuple[int, int],
    *,
    triangle_mask: np.ndarray | None = None,
    depth: np.ndarray | None = None,
) -> Raster:
    """Every pixel centre of `shape` inside a (masked) triangle; with `depth` (N,) the nearest
    triangle wins where triangles overlap (larger z is nearer), else the later one."""
    height, width = shape
    points = np.asarray(points_px, dtype=np.float64)
    labels = triangle_labels(points, triangles, shape, triangle_mask=triangle_mask, depth=depth)
    ys, xs = np.nonzero(labels >= 0)
    tri = labels[ys, xs]
    px = np.column_stack([xs, ys]).astype(np.float64)
    bary = _barycentric(points, triangles, tri, px)
    inside = np.all(bary >= -1e-6, axis=1)
    # fillPoly's edge pixels may lie a fraction of a pixel outside their triangle (and a later
    # neighbour overwrites the label): clamp them onto it rather than leave cracks.
    bary = np.clip(bary, 0.0, None)
    bary /= bary.sum(axis=1, keepdims=True)
    return Raster(
        ys=ys,
        xs=xs,
        tri=tri,
        bary=bary.astype(np.float32),
        corners=triangles[tri],
        shape=(height, width),
        inside=inside,
    )


def warp_points(raster: Raster, points_px: np.ndarray) -> np.ndarray:
    """Where each raster pixel lands when the vertices move to `points_px` (..., N, 2) -> (..., K, 2).

    float32. For a batch of point sets the result is one sparse product with the raster's
    barycentric weights, laid out pixel-major in memory (a transposed view; the point-set axis is
    the innermost): 500 sets on a 4,400-pixel template take about 2 ms here, and
    `sample_bilinear` reads that layout without a copy.
    """
    points = np.asarray(points_px, dtype=np.float32)
    lead, n = points.shape[:-2], points.shape[-2]
    count = int(np.prod(lead, dtype=np.int64))
    if count < _BATCH_MIN:
        corners = points[..., raster.corners, :]  # (..., K, 3, 2)
        return np.einsum("kj,...kjd->...kd", raster.bary, corners)
    # (N, 2 * count): every set's x column, then every set's y column.
    columns = np.ascontiguousarray(points.reshape(count, n, 2).transpose(1, 2, 0)).reshape(n, -1)
    warped = raster.weights(n) @ columns  # (K, 2 * count)
    return np.moveaxis(warped.reshape(raster.size, 2, count), 2, 0).reshape(lead + (raster.size, 2))


def sample_bilinear(image: np.ndarray, xy: np.ndarray, *, fill: float | None = None) -> np.ndarray:
    """Bilinear samples of `image` at `xy` (..., K, 2); outside the image the border repeats, or
    `fill` when given. Returns (..., K) float32, or (..., K, C) for a colour image.

    cv2.remap does the work: it quantises sub-pixel positions to 1/32 pixel. 500 x 4,400
    samples take 2-5 ms here.
    """
    import cv2

    xy = np.asarray(xy, dtype=np.float32)
    lead, k = xy.shape[:-2], xy.shape[-2]
    count = int(np.prod(lead, dtype=np.int64))
    border = cv2.BORDER_REPLICATE if fill is None else cv2.BORDER_CONSTANT
    source = image if image.dtype in (np.uint8, np.float32) else image.astype(np.float32)
    channels = () if image.ndim == 2 else (image.shape[2],)

    def remap(map_x: np.ndarray, map_y: np.ndarray | None) -> np.ndarray:
        return cv2.remap(
            source, map_x, map_y, cv2.INTER_LINEAR, borderMode=border, borderValue=fill or 0
        )

    if 0 < k < _REMAP_MAX and 0 < count < _REMAP_MAX:
        # Any 2-D arrangement of the points is a valid map: use the one the memory already has.
        planes = xy.reshape(count, k, 2)
        step = xy.itemsize
        if planes.strides[0] == step and count > 1:  # set axis innermost (`warp_points`)
            out = remap(planes[..., 0].T, planes[..., 1].T)
            out = np.moveaxis(out, 1, 0)
        elif planes.strides[1] == step:  # x and y planes per set
            out = remap(planes[..., 0], planes[..., 1])
        else:
            out = remap(np.ascontiguousarray(planes), None)
        return out.astype(np.float32, copy=False).reshape(lead + (k,) + channels)
    # Too long for one map row (cv2 maps are narrower than 32767): wrap the points into rows.
    flat = xy.reshape(-1, 2)
    total = flat.shape[0]
    if total == 0:
        return np.zeros(lead + (k,) + channels, dtype=np.float32)
    rows = -(-total // _REMAP_COLS)
    padded = np.zeros((rows * _REMAP_COLS, 2), dtype=np.float32)
    padded[:total] = flat
    out = remap(padded.reshape(rows, _REMAP_COLS, 2), None)
    out = out.reshape((rows * _REMAP_COLS,) + channels)[:total]
    return out.astype(np.float32, copy=False).reshape(lead + (k,) + channels)


def render(
    texture: np.ndarray,
    texture_points_px: np.ndarray,
    target_points_px: np.ndarray,
    triangles: np.ndarray,
    out_shape: tuple[int, int],
    *,
    visible: np.ndarray | None = None,
    depth: np.ndarray | None = None,
    background: np.ndarray | None = None,
) -> RenderResult:
    """Texture-map `texture` (its mesh at `texture_points_px`) onto a mesh at `target_points_px`."""
    raster = rasterize(target_points_px, triangles, out_shape, triangle_mask=visible, depth=depth)
    source_xy = warp_points(raster, np.asarray(texture_points_px))
    values = sample_bilinear(texture, source_xy)
    if background is None:
        image = np.zeros(out_shape + texture.shape[2:], dtype=texture.dtype)
    else:
        image = background.copy()
    if np.issubdtype(image.dtype, np.integer):
        values = np.clip(np.rint(values), 0, np.iinfo(image.dtype).max)
    image[raster.ys, raster.xs] = values.astype(image.dtype)
    mask = np.zeros(out_shape, dtype=bool)
    mask[raster.ys, raster.xs] = True
    return RenderResult(image=image, mask=mask)
