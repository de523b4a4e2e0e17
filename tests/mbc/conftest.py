import numpy as np
import pytest

from uma.face.talking_head import TalkingHeadSource


@pytest.fixture(scope="session")
def head() -> TalkingHeadSource:
    """The built-in talking head at CIF (ground truth exact)."""
    return TalkingHeadSource(352, 288, seed=3)


@pytest.fixture(scope="session")
def head_frames(head: TalkingHeadSource) -> list[np.ndarray]:
    """Its first 12 frames, gray, with sensor noise."""
    import cv2

    rng = np.random.default_rng(3)
    return [cv2.cvtColor(head.render_bgr(i, rng=rng), cv2.COLOR_BGR2GRAY) for i in range(12)]
