"""The value types every section of the scenario schema is made of, and the section base.

Numbers must be numbers (a string such as "2 Mbit/s" is refused, so a unit cannot hide in a
value); sections are frozen and refuse unknown keys.
"""

from __future__ import annotations

from typing import Annotated

from pydantic import AllowInfNan, BaseModel, ConfigDict, Field, Strict

__all__ = ["Num", "PosNum", "NonNeg", "Fraction", "PosInt", "NonNegInt", "Bool", "Str", "Section"]

Num = Annotated[float, Strict(), AllowInfNan(False)]
PosNum = Annotated[float, Strict(), AllowInfNan(False), Field(gt=0)]
NonNeg = Annotated[float, Strict(), AllowInfNan(False), Field(ge=0)]
Fraction = Annotated[float, Strict(), AllowInfNan(False), Field(ge=0, le=1)]
PosInt = Annotated[int, Strict(), Field(gt=0)]
NonNegInt = Annotated[int, Strict(), Field(ge=0)]
Bool = Annotated[bool, Strict()]
Str = Annotated[str, Strict()]


class Section(BaseModel):
    """A part of the scenario: frozen, unknown keys refused."""

    model_config = ConfigDict(frozen=True, extra="forbid")
