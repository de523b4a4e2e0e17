"""The value types every section of the scenario schema is made of, and the section base.

Numbers must be numbers (a string such as "2 Mbit/s" is refused, so a unit cannot hide in a
value); sections are frozen and refuse unknown keys.
"""

from __future__ import annotations

from typing import Annotated

from pydantic import AllowInfNan, BaseModel, ConfigDict, Field, Strict

__all__ = [
    "Num",
    "PosNum",
    "NonNeg",
    "Fraction",
    "PosInt",
    "NonNegInt",
    "Bool",
    "Str",
    "Section",
    "MAX_NUMBER",
    "MAX_INT",
    "bounded",
]

# No key of a run means anything near these (1e9 kbit/s is a terabit, 1e9 ms eleven days, 1e9
# bytes a gigabyte); a key with a tighter meaning is bounded where it is declared. Beyond them
# a value would overflow the arrays and counters a run keeps.
MAX_NUMBER = 1e9
MAX_INT = 10**9

Num = Annotated[float, Strict(), AllowInfNan(False), Field(ge=-MAX_NUMBER, le=MAX_NUMBER)]
PosNum = Annotated[float, Strict(), AllowInfNan(False), Field(gt=0, le=MAX_NUMBER)]
NonNeg = Annotated[float, Strict(), AllowInfNan(False), Field(ge=0, le=MAX_NUMBER)]
Fraction = Annotated[float, Strict(), AllowInfNan(False), Field(ge=0, le=1)]
PosInt = Annotated[int, Strict(), Field(gt=0, le=MAX_INT)]
NonNegInt = Annotated[int, Strict(), Field(ge=0, le=MAX_INT)]


def bounded(low: float, high: float, *, integer: bool = False, open_low: bool = False):
    """A number type within [low, high] (or (low, high] with `open_low`), strict and finite."""
    low_bound = Field(gt=low) if open_low else Field(ge=low)
    if integer:
        return Annotated[int, Strict(), low_bound, Field(le=high)]
    return Annotated[float, Strict(), AllowInfNan(False), low_bound, Field(le=high)]


Bool = Annotated[bool, Strict()]
Str = Annotated[str, Strict()]


class Section(BaseModel):
    """A part of the scenario: frozen, unknown keys refused."""

    model_config = ConfigDict(frozen=True, extra="forbid")
