"""Which point to be on when the engine may switch codec families: the switching policy's
choice, carried through the model codec's sub-machine and the description's delivery.

Units: times in seconds, rates in kbit/s.

The switching policy names a family: the rate ladder's (its full-frame codec) or the model
codec's. For the rate ladder the rate policy chooses the rung, and any initialisation under way
is abandoned. For the model codec the sub-machine says what to do (`uma.engine.model.Want`):
its point once it is initialised, the rate policy's rung while an initialisation runs or the
description is still on its way (that wait is timed), the lowest rung while it is refused,
or start an initialisation now.
"""

from __future__ import annotations

from collections.abc import Callable

from uma.engine.description import Delivery
from uma.engine.ladder import Ladder
from uma.engine.model import ModelMachine, Want
from uma.engine.policy import PolicyView, SwitchSettings, SwitchView

__all__ = ["Switcher"]


class Switcher:
    """The switching decision for one frame, over the engine's parts it is given."""

    def __init__(
        self,
        policy: Callable[[SwitchView, SwitchSettings], str],
        settings: SwitchSettings,
        *,
        ladder: Ladder,
        model: ModelMachine,
        description: Delivery,
        coverage: tuple[tuple[float, str], ...] = (),
    ) -> None:
        self.policy = policy
        self.settings = settings
        self.ladder = ladder
        self.model = model
        self.description = description
        self.coverage = coverage

    def choose(
        self,
        view: PolicyView,
        rate_policy: Callable[[PolicyView], int],
        *,
        since_s: float,
        budget_kbps: float,
        budget_ahead_kbps: float | None,
        cut_s: float = float("-inf"),
    ) -> tuple[int, int | None, list]:
        """The point to be on, the model point to start initialising now (or None), and the
        actions the choice caused; `cut_s`: when the estimate was last cut for a silence."""
        now_s = view.now_s
        family = self.policy(
            SwitchView(
                now_s,
                self.ladder.family(view.current),
                since_s,
                budget_kbps,
                coverage=self.coverage,
                budget_ahead_kbps=budget_ahead_kbps,
                cut_s=cut_s,
            ),
            self.settings,
        )
        if family != self.model.name:
            self.description.stop_wait(now_s)
            return rate_policy(view), None, self.model.leave(now_s)
        want = self.model.want(now_s, description_ready=not self.description.pending)
        if want is Want.MODEL:
            self.model.use()
            return self.ladder.model_point, None, []
        if want is Want.LOWEST:
            return self.ladder.allowed(now_s)[0], None, self.model.refuse(now_s)
        if want is Want.START:
            actions = self.model.start(now_s, budget_kbps)
            return rate_policy(view), self.ladder.model_point, actions
        actions = []
        if want is Want.WAIT:  # wanted, but the receiver cannot render it yet: time counted
            actions = self.description.wait(now_s)
        return rate_policy(view), None, actions
