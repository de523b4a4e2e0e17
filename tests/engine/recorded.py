"""A part of the engine with the actions its calls return kept, as the engine keeps them."""

from uma.engine.records import EngineEvent, Tally


class Recorded:
    """Proxies `part`; each call's returned actions are kept in `events` ((time, kind, detail))
    and `counts`; a call returning (value, actions) returns the value."""

    def __init__(self, part):
        self.part, self.events, self.counts = part, [], {}

    def keep(self, actions):
        for action in actions:
            if isinstance(action, EngineEvent):
                self.events.append((action.time_s, action.kind, action.detail))
            elif isinstance(action, Tally):
                self.counts[action.key] = self.counts.get(action.key, 0) + action.n
        return actions

    def __getattr__(self, name):
        attr = getattr(self.part, name)
        if not callable(attr):
            return attr

        def call(*args, **kwargs):
            out = attr(*args, **kwargs)
            if isinstance(out, tuple) and len(out) == 2 and isinstance(out[1], list):
                self.keep(out[1])
                return out[0]
            return self.keep(out) if isinstance(out, list) else out

        return call
