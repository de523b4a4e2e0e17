"""One pose's rotation is the batch's to the bit (the renderer and the tracker call it with one
pose, the fitting with batches: both must place the model at the same points)."""

from __future__ import annotations

import numpy as np

from uma.face.geometry import rotation_matrix


def test_one_pose_rotation_is_the_batched_one_to_the_bit() -> None:
    rng = np.random.default_rng(3)
    angles = rng.uniform(-3.5, 3.5, (2000, 3))
    angles[:10] = 0.0
    angles[10:20] *= 1e-9
    batch = rotation_matrix(angles[:, 0], angles[:, 1], angles[:, 2])
    for (rx, ry, rz), expected in zip(angles, batch, strict=True):
        for one in (rotation_matrix(rx, ry, rz), rotation_matrix(float(rx), float(ry), float(rz))):
            assert one.shape == (3, 3) and one.dtype == np.float64
            assert np.array_equal(one, expected)


def test_one_pose_rotation_is_a_rotation_about_each_axis() -> None:
    quarter = np.pi / 2
    assert np.allclose(rotation_matrix(0.0, 0.0, quarter) @ [1.0, 0.0, 0.0], [0.0, 1.0, 0.0])
    assert np.allclose(rotation_matrix(0.0, quarter, 0.0) @ [0.0, 0.0, 1.0], [1.0, 0.0, 0.0])
    assert np.allclose(rotation_matrix(quarter, 0.0, 0.0) @ [0.0, 1.0, 0.0], [0.0, 0.0, 1.0])
    mixed = rotation_matrix(0.3, -0.7, 1.1)
    assert np.allclose(mixed @ mixed.T, np.eye(3))
