"""Argument types shared by the sub-commands: range expansion is bounded."""

from __future__ import annotations

import pytest

from simgrasp.cli.options import MAX_RANGE_VALUES, float_range
from simgrasp.errors import SimgraspError


def test_a_range_expands_inclusive_of_stop() -> None:
    assert float_range("0:0.1:0.02") == (0.0, 0.02, 0.04, 0.06, 0.08, 0.1)
    assert float_range("0,0.05") == (0.0, 0.05)


@pytest.mark.parametrize(
    ("text", "reason"),
    [
        ("0:inf:0.1", "finite"),
        ("nan:1:0.1", "finite"),
        ("0:0.5:inf", "finite"),
        ("0,nan", "finite"),
        ("0:0.5:1e-12", f"at most {MAX_RANGE_VALUES}"),
        ("0:1:0.0001", f"at most {MAX_RANGE_VALUES}"),
    ],
)
def test_an_unbounded_range_is_refused_saying_why(text: str, reason: str) -> None:
    with pytest.raises(SimgraspError, match=reason):
        float_range(text)


def test_the_largest_allowed_range_expands() -> None:
    assert len(float_range(f"0:{MAX_RANGE_VALUES - 1}:1")) == MAX_RANGE_VALUES
