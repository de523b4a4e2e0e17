import pytest

from uma.bench.init_cases import _astronaut_template, make_cases
from uma.face import load_model


@pytest.fixture(scope="session")
def template():
    """The built-in astronaut at 92x112 with the model placed on her clicked points."""
    return _astronaut_template(load_model())


@pytest.fixture(scope="session")
def cases(template):
    """Three renderings of the astronaut at random known poses (ground truth exact)."""
    return make_cases([template], 3, rng=11)
