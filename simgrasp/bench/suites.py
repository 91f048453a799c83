"""The benchmark's suites: frozen lists of scenes, each fixed by its definition and its hash.

A suite is a :class:`SuiteDefinition`: blocks of scenes (each block the product of objects,
placements, clutter counts, sensors and seeds), the trial protocol, the gripper, the views
and the oracle's budget. Everything a scene's outcome depends on is a field of the
definition, so :meth:`SuiteDefinition.digest` (SHA-256 of its JSON) names exactly one set of
scenes; every record carries it, and a run that finds records of another digest in its
output folder refuses to resume. A changed definition is a new version (``handles-v2``),
never an edit of ``handles-v1``.

Free of MuJoCo imports: ``simgrasp bench list`` and the command line read it.
"""

from __future__ import annotations

import hashlib
import itertools
import json
import os
from dataclasses import asdict, dataclass, replace
from typing import Any

from simgrasp.errors import DataNotFoundError, SimgraspError

DISTRACTORS = "gen_mug,gen_hammer,gen_spatula,gen_screwdriver,gen_pan,gen_can,gen_fruit"
"""The distractors of every cluttered bench scene: an explicit list (not a set name such as
``all``, whose members depend on the machine's YCB folder), so a scene is the same
everywhere."""
YCB_HANDLE_OBJECTS = (
    "019_pitcher_base",
    "025_mug",
    "030_fork",
    "031_spoon",
    "032_knife",
    "033_spatula",
    "035_power_drill",
    "037_scissors",
    "042_adjustable_wrench",
    "043_phillips_screwdriver",
    "044_flat_screwdriver",
    "048_hammer",
)
"""The YCB objects whose label (``models/handles/ycb_handles.json``) has a handle region."""
GENERATED_HANDLE_OBJECTS = (
    "gen_mug_s0",
    "gen_mug_s1",
    "gen_hammer_s0",
    "gen_hammer_s1",
    "gen_spatula_s0",
    "gen_spatula_s1",
    "gen_screwdriver_s0",
    "gen_screwdriver_s1",
    "gen_pan_s0",
    "gen_pan_s1",
    "gen_strap_mug_s0",
    "gen_strap_mug_s1",
    "gen_drill_s0",
)
"""Generated tools with a labeled handle that can stand upright: two sizes of the five main
kinds and of the strap mug, and a drill (the generated wrench has no upright pose)."""


@dataclass(frozen=True)
class SceneBlock:
    """Scenes that are the product of these axes (every combination, in this order)."""

    objects: tuple[str, ...]
    placements: tuple[str, ...] = ("stable", "upright")
    clutters: tuple[int, ...] = (0, 5)
    sensors: tuple[str, ...] = ("ideal", "kinect")
    seeds: tuple[int, ...] = (0,)


@dataclass(frozen=True)
class OracleBudget:
    """How hard the oracle tries per scene: antipodal grasps sampled on the object's mesh
    (``samples``), of which at most ``handle_trials`` on the labeled handle and then at most
    ``lift_trials`` elsewhere are executed, each series stopping at its first success."""

    samples: int = 96
    handle_trials: int = 8
    lift_trials: int = 4
    rounds: int = 24
    """Sampling rounds (512 surface points each) before the sampler stops short of
    ``samples``: a pan lying on its rim offers few grasps clear of the table (the sampler's
    default 200 rounds took 35 s there), a knife lying flat few at all (none in 6 rounds,
    12 in 60)."""


@dataclass(frozen=True)
class BenchScene:
    """One scene of a suite: its id (``SUITE/INDEX-OBJECT-...``-free: ``0007-gen_mug_s0-
    upright-c5-kinect-s0``), what rests where, and how it is seen."""

    index: int
    object: str
    placement: str
    clutter: int
    sensor: str
    seed: int

    @property
    def id(self) -> str:
        """The scene's folder and file name: index, object, placement, clutter, sensor, seed."""
        return (
            f"{self.index:04d}-{self.object}-{self.placement}-c{self.clutter}-"
            f"{self.sensor}-s{self.seed}"
        )

    @property
    def world(self) -> str:
        """What the scene's outcome of a given grasp depends on (its id without the index
        and the sensor): the oracle's key, shared by the scenes that differ only in how
        they are seen."""
        return f"{self.object}-{self.placement}-c{self.clutter}-s{self.seed}"

    @property
    def needs_ycb(self) -> bool:
        """Whether the scene's object is read from the YCB folder."""
        return not self.object.startswith("gen_")

    def axes(self) -> dict[str, Any]:
        """The fields a report groups by."""
        return {
            "object": self.object,
            "placement": self.placement,
            "clutter": self.clutter,
            "sensor": self.sensor,
        }


@dataclass(frozen=True)
class SuiteDefinition:
    """A suite: its name, scene blocks and everything a scene's outcome depends on.

    Attributes:
        name: the suite's versioned name (``handles-v1``).
        summary: one line for ``simgrasp bench list``.
        blocks: the scenes, block by block.
        views: cameras per scene (the chain's default viewpoints around the object).
        gripper: the gripper that executes every grasp.
        protocol: the trial protocol (:mod:`simgrasp.grasping.trials.protocol`).
        distractors: what cluttered scenes draw their neighbors from (a comma list).
        oracle: the oracle's budget per scene.
        only: when not empty, the indices of the scenes kept (a part of a suite, e.g. for a
            quick test; its digest differs from the whole suite's).
    """

    name: str
    summary: str
    blocks: tuple[SceneBlock, ...]
    views: int = 4
    gripper: str = "builtin"
    protocol: str = "full"
    distractors: str = DISTRACTORS
    oracle: OracleBudget = OracleBudget()
    only: tuple[int, ...] = ()

    def scenes(self) -> tuple[BenchScene, ...]:
        """Every scene, in a fixed order (indices count across blocks)."""
        combos = [
            combo
            for block in self.blocks
            for combo in itertools.product(
                block.objects, block.placements, block.clutters, block.sensors, block.seeds
            )
        ]
        scenes = tuple(BenchScene(i, *combo) for i, combo in enumerate(combos))
        return tuple(s for s in scenes if s.index in self.only) if self.only else scenes

    def digest(self) -> str:
        """SHA-256 (hex) of the definition's JSON: the identity every record carries."""
        text = json.dumps(asdict(self), sort_keys=True, separators=(",", ":"))
        return hashlib.sha256(text.encode()).hexdigest()

    def part(self, indices: tuple[int, ...]) -> SuiteDefinition:
        """The suite cut to the scenes of ``indices`` (a new digest)."""
        known = {s.index for s in self.scenes()}
        if missing := sorted(set(indices) - known):
            raise SimgraspError(f"suite {self.name} has no scene index {missing[0]}")
        return replace(self, only=tuple(sorted(indices)))

    def scene(self, scene_id: str) -> BenchScene:
        """The scene of ``scene_id``; an error naming the suite when it has none."""
        for scene in self.scenes():
            if scene.id == scene_id:
                return scene
        raise SimgraspError(f"suite {self.name} has no scene {scene_id!r}")


SUITES: dict[str, SuiteDefinition] = {
    suite.name: suite
    for suite in (
        SuiteDefinition(
            "handles-v1",
            "YCB handle objects and generated tools x stable/upright x clutter 0/5 x "
            "ideal/kinect depth",
            (SceneBlock(YCB_HANDLE_OBJECTS + GENERATED_HANDLE_OBJECTS),),
        ),
        SuiteDefinition(
            "handles-mini",
            "generated mug, hammer and pan: stable/upright, alone with ideal depth or among "
            "5 with kinect depth (tests, CI)",
            (
                SceneBlock(
                    ("gen_mug_s0", "gen_hammer_s0", "gen_pan_s0"), clutters=(0,), sensors=("ideal",)
                ),
                SceneBlock(
                    ("gen_mug_s0", "gen_hammer_s0", "gen_pan_s0"),
                    clutters=(5,),
                    sensors=("kinect",),
                ),
            ),
            oracle=OracleBudget(samples=64, handle_trials=6, lift_trials=3, rounds=6),
        ),
    )
}
"""The suites, by name. Frozen: a change is a new name."""


def suite_by_name(name: str) -> SuiteDefinition:
    """The suite ``name``; an error listing the suites otherwise."""
    if name not in SUITES:
        raise SimgraspError(f"unknown suite {name!r}; choose one of {', '.join(SUITES)}")
    return SUITES[name]


def check_suite_data(suite: SuiteDefinition) -> None:
    """One line naming what is missing when the suite has YCB scenes and no YCB folder is
    set (``$SIMGRASP_YCB_DIR``)."""
    ycb = [s for s in suite.scenes() if s.needs_ycb]
    if ycb and not os.environ.get("SIMGRASP_YCB_DIR"):
        raise DataNotFoundError(
            f"suite {suite.name} has {len(ycb)} scenes of YCB objects: set SIMGRASP_YCB_DIR "
            "to a YCB folder (simgrasp fetch-ycb)"
        )
