"""Named detector settings: each says what it is for and which results page measures it.

A preset is a whole settings value of one detector (the quadric detector's
:class:`~simgrasp.handles.core.config.QuadricDetectorConfig`, the single-view detector's
:class:`~simgrasp.handles.single_view.detector.SingleViewConfig` or ten Pas's
:class:`~simgrasp.handles.baselines.tenpas_config.TenPasConfig`), built fresh on every call.
``simgrasp detect-eval --real MANIFEST --real-configs NAME,...`` compares presets by name, the
chain's detector defaults to :data:`CHAIN_PRESET` and the single-view detector that
``simgrasp detect`` runs on a camera's view to :data:`SINGLE_VIEW_PRESET`. A new preset is one
:class:`Preset` in :data:`PRESETS` (or :func:`register_preset` at run time).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, replace
from typing import Any, TypeVar

from simgrasp.errors import SimgraspError
from simgrasp.handles.baselines.tenpas_config import TenPasConfig
from simgrasp.handles.core.config import QuadricDetectorConfig
from simgrasp.handles.single_view.body_wall import BodyWallConfig
from simgrasp.handles.single_view.detector import SingleViewConfig
from simgrasp.registry import Registry

DetectorSetting = QuadricDetectorConfig | TenPasConfig | SingleViewConfig
"""The settings of one handle detector."""
Setting = TypeVar("Setting", QuadricDetectorConfig, TenPasConfig, SingleViewConfig)


@dataclass(frozen=True)
class Preset:
    """A named detector setting: ``build`` makes it, ``purpose`` says in one sentence what it
    is for, ``results`` names the results folder ``docs/results/RESULTS/`` whose runs measure
    it (its page: the folder's README.md, or its section of docs/results/README.md)."""

    name: str
    build: Callable[[], DetectorSetting]
    purpose: str
    results: str


def _paper() -> QuadricDetectorConfig:
    return QuadricDetectorConfig(
        eccentricity_test=False, width_test=False, shell_test=False, inside_test=False
    )


def _two_scales() -> QuadricDetectorConfig:
    return QuadricDetectorConfig(fine_half_size=0.012)


def _camera_cloud() -> QuadricDetectorConfig:
    return QuadricDetectorConfig(
        own_normals=True,
        normal_radius=0.006,
        neighborhood_half_size=0.012,
        voxels_per_neighborhood=1.0,
    )


def _noisy_camera_cloud() -> QuadricDetectorConfig:
    return replace(_camera_cloud(), fit_method="taubin", shell_thickness=0.006)


def _real_depth() -> QuadricDetectorConfig:
    return QuadricDetectorConfig(
        neighborhood_half_size=0.012,
        voxels_per_neighborhood=2.0,
        handle_anchor="surface",
        prefer_central=False,
        plate_test=True,
    )


def _learned() -> SingleViewConfig:
    return SingleViewConfig(
        classifier=True,
        classifier_threshold=0.7,
        grid_rolls=3,
        min_width_spacings=2.0,
        narrow_width_spacings=1.0,
        body_wall=BodyWallConfig(enabled=True, retry_threshold=0.5),
        fallback=_real_depth(),
    )


PRESETS: Registry[Preset] = Registry(
    "detector preset",
    (
        Preset(
            "default",
            QuadricDetectorConfig,
            "what `simgrasp detect` runs: the quadric detector's defaults, and on a cloud "
            "measured to be one camera's view the single-view detector (`learned`, its "
            "`real_depth` fallback where the classifier keeps nothing)",
            "real-detect",
        ),
        Preset(
            "multi_view",
            QuadricDetectorConfig,
            "the quadric detector's defaults on every cloud, the single-view detector never "
            "chosen: what the single-view detector is measured against",
            "real-detect",
        ),
        Preset(
            "paper",
            _paper,
            "the paper's criteria (a)-(c) alone, no eccentricity, width, shell or inside test: "
            "the method as published",
            "real-detect",
        ),
        Preset(
            "two_scales",
            _two_scales,
            "fused clouds of rendered depth views: the defaults plus a fine pass (Taubin fits "
            "of 12 mm neighborhoods, one center per 3 voxels, a 6 mm shell) that keeps thin "
            "handles seen from two sides (a lying mug's strap); the chain's default",
            "lying-mug",
        ),
        Preset(
            "camera_cloud",
            _camera_cloud,
            "fused clouds of rendered depth views, an alternative to `two_scales`: normals of "
            "its own over 6 mm and 12 mm neighborhoods sampled ten times as densely",
            "lying-mug",
        ),
        Preset(
            "noisy_camera_cloud",
            _noisy_camera_cloud,
            "`camera_cloud` for a noisy depth sensor's fused clouds (`--sensor kinect`): "
            "Taubin fits, which use no normals, and a 6 mm shell",
            "lying-mug",
        ),
        Preset(
            "real_depth",
            _real_depth,
            "one object cut from a single real depth view (a Kinect-class sensor at 0.6-1.6 "
            "m): 12 mm neighborhoods sampled five times as densely, centers on the seen "
            "surface, no centrality weighting and the flat-plate test (a pot's side tab)",
            "real-pots",
        ),
        Preset(
            "tenpas",
            TenPasConfig,
            "ten Pas & Platt's cylindrical shells, the baseline the quadric detector is "
            "compared with",
            "detect-eval",
        ),
        Preset(
            "standoff",
            SingleViewConfig,
            "the single-view detector with the hand-written standoff test (free space for "
            "the fingers on both sides of a candidate) instead of the classifier",
            "real-detect",
        ),
        Preset(
            "learned",
            _learned,
            "the single-view detector that `simgrasp detect` runs on a camera's view: the "
            "shipped classifier at 0.7 on fits at least two point spacings wide (or one, with "
            "the axis within four half widths of the surface), candidates on the view's body "
            "wall dropped, the `real_depth` quadric detector where nothing is kept",
            "real-detect",
        ),
    ),
    choose="choose from",
)
"""The shipped presets by name."""

CHAIN_PRESET = "two_scales"
"""The quadric detector's settings in the full chain (``trial``, ``evaluate``)."""
SINGLE_VIEW_PRESET = "learned"
"""The single-view detector's settings in ``detect`` and :func:`simgrasp.detect_handles`."""


def preset_names() -> tuple[str, ...]:
    """The registered presets' names."""
    return PRESETS.names()


def preset(name: str) -> DetectorSetting:
    """The preset ``name``, built now; one line naming the choices when it is unknown."""
    return PRESETS.entry(name).build()


def typed_preset(name: str, kind: type[Setting], **overrides: Any) -> Setting:
    """The preset ``name`` as a ``kind`` settings value, with ``overrides`` of its fields; an
    error when that preset is another detector's."""
    built = preset(name)
    if not isinstance(built, kind):
        raise SimgraspError(f"detector preset {name!r} is no {kind.__name__}")
    return replace(built, **overrides)


def quadric_preset(name: str, **overrides: Any) -> QuadricDetectorConfig:
    """The quadric detector's preset ``name`` with ``overrides``."""
    return typed_preset(name, QuadricDetectorConfig, **overrides)


def single_view_preset(name: str = SINGLE_VIEW_PRESET, **overrides: Any) -> SingleViewConfig:
    """The single-view detector's preset ``name`` (default: what ``detect`` runs) with
    ``overrides``."""
    return typed_preset(name, SingleViewConfig, **overrides)


def chain_quadric() -> QuadricDetectorConfig:
    """The quadric detector's settings in the full chain (:data:`CHAIN_PRESET`)."""
    return quadric_preset(CHAIN_PRESET)


def register_preset(entry: Preset) -> None:
    """Add a preset at run time (its name must be new)."""
    PRESETS.register(entry)
