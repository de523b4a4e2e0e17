"""Each end pays for its own references: the receiver cuts and fills a refresh itself, whatever
the engine's mirror took before it in the same process (nothing is shared through module state,
as the memos removed in session 20 were)."""

from __future__ import annotations

import numpy as np

from uma.mbc import layers
from uma.mbc.refresh_coder import take_refresh
from uma.mbc.scene_render import SceneRenderer
from uma.mbc.units import FaceUnits

SIZE = (352, 288)


def _refresh(head):
    """A decoded set of frame 3 and a refresh box: what both ends take."""
    units = FaceUnits.of(head.model, head.description.params, light=True, body=True)
    values = np.concatenate([head.params_at(3), (2.0, -1.0, 0.01), (1.0, 0.0)])
    patch = np.full((96 * 3 // 2, 64), 90, np.uint8)
    return units, values, ((100, 60), patch)


def _counted(monkeypatch) -> dict:
    """Counts of the person's cuts (its torso outline) and the plate's luma fills (Telea)."""
    counts = {"cuts": 0, "luma_fills": 0}
    polygon, edges = layers.torso_polygon, layers._continue_edges

    def torso_polygon(*args, **kwargs):
        counts["cuts"] += 1
        return polygon(*args, **kwargs)

    def continue_edges(filled, known, edge, *args, **kwargs):
        counts["luma_fills"] += edge == "telea"
        return edges(filled, known, edge, *args, **kwargs)

    monkeypatch.setattr(layers, "torso_polygon", torso_polygon)
    monkeypatch.setattr(layers, "_continue_edges", continue_edges)
    return counts


def test_the_receiver_cuts_and_fills_a_refresh_the_mirror_took_before_it(head, monkeypatch):
    mirror, receiver = SceneRenderer(head.description, SIZE), SceneRenderer(head.description, SIZE)
    mirror.set_luma_only(True)
    units, values, picture = _refresh(head)
    take_refresh(mirror, units, values, picture)
    counts = _counted(monkeypatch)
    take_refresh(receiver, units, values, picture)
    assert counts == {"cuts": 1, "luma_fills": 1}  # its own, not the mirror's kept ones
    height = SIZE[1]
    assert np.array_equal(receiver.person_mask, mirror.person_mask)
    assert np.array_equal(receiver.plate.picture[:height], mirror.plate.picture[:height])
