"""CI draws the same hypothesis examples every run; local runs draw new ones."""

import os

from hypothesis import settings


def test_profile_follows_the_environment():
    wanted = os.environ.get("HYPOTHESIS_PROFILE") or ("ci" if os.environ.get("CI") else "dev")
    assert settings().derandomize == (wanted == "ci")
    assert settings.get_profile("ci").derandomize
    assert not settings.get_profile("dev").derandomize
