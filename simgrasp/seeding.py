"""One seed for every random choice: derive independent, reproducible generators from it."""

from __future__ import annotations

import zlib

import numpy as np

from simgrasp.errors import SimgraspError


def rng_for(seed: int, *keys: str | int) -> np.random.Generator:
    """Return a generator determined by ``seed`` and a path of keys.

    Different key paths give statistically independent streams, so adding a random choice in
    one stage never shifts the draws of another stage.
    """
    if not isinstance(seed, int | np.integer) or seed < 0:
        raise SimgraspError(f"seed must be a non-negative integer, got {seed!r}")
    words = [int(seed)] + [k if isinstance(k, int) else zlib.crc32(str(k).encode()) for k in keys]
    return np.random.default_rng(np.random.SeedSequence(words))
