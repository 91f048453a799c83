"""A knife's automatic label ends where its handle's even run ends
(simgrasp.autolabel.handle_run): a blade as thick as the handle stays off it (and, with the
bolster cut, a bolster), on generated knives with exact labels and on section profiles whose
answer is known."""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from simgrasp.assets.generated import generate_parts, generate_tool
from simgrasp.autolabel.auto_label import auto_handle_label
from simgrasp.autolabel.config import AutoLabelConfig
from simgrasp.autolabel.cross_section import CrossSectionConfig, SectionProfile
from simgrasp.autolabel.handle_run import even_run, handle_span
from simgrasp.autolabel.virtual_scan import ScanConfig
from simgrasp.labels import HandleLabel
from simgrasp.perception import sample_surface

CONFIG = CrossSectionConfig(span_share=0.75)
"""The span cut on (it is off by default)."""
FAST = AutoLabelConfig(scan=ScanConfig(views=12), cross_section=CONFIG)
SLAB = 0.002


def _iou(found: HandleLabel, exact: HandleLabel, mesh: object) -> float:
    """Intersection over union of the two labels on points sampled on the mesh."""
    points, _ = sample_surface(mesh, 20000, np.random.default_rng(0))  # type: ignore[arg-type]
    a, b = found.contains(points), exact.contains(points)
    return float((a & b).sum() / max((a | b).sum(), 1))


def _label_and_blade(kind: str, seed: int, config: AutoLabelConfig = FAST) -> tuple[float, float]:
    """The IoU of a generated knife's automatic label with its exact one, and the share of its
    blade's surface the label holds."""
    asset = generate_tool(kind, seed)
    label = auto_handle_label(asset.mesh, asset.name, config).label
    blade = next(p.mesh for p in generate_parts(kind, seed).parts if p.name == "blade")
    return _iou(label, asset.handle, asset.mesh), float(
        label.contains(blade.sample(4000, seed=0)).mean()
    )


def test_a_blade_as_thick_as_its_handle_stays_off_the_label() -> None:
    iou, on_blade = _label_and_blade("table_knife", 10)  # 0.59 and 0.96 of the blade without
    assert iou >= 0.85
    assert on_blade <= 0.1


def test_a_bolster_stays_off_a_chef_knife_label_with_the_bolster_cut() -> None:
    iou, on_blade = _label_and_blade("chef_knife", 11)  # without it the bolster is labeled
    assert iou >= 0.8
    assert on_blade <= 0.15
    section = replace(FAST.cross_section, bolster_reach=0.02)
    iou, on_blade = _label_and_blade("chef_knife", 11, replace(FAST, cross_section=section))
    assert iou >= 0.92
    assert on_blade <= 0.05


def _profile(thickness: list[float], width: list[float]) -> SectionProfile:
    """A profile along x from 0 with slabs of :data:`SLAB` (m)."""
    return SectionProfile(
        np.zeros(3), np.array([1.0, 0.0, 0.0]), 0.0, SLAB, np.array(thickness), np.array(width)
    )


def _at(slabs: np.ndarray) -> np.ndarray:
    """Points at the middle of ``slabs`` (m)."""
    return np.column_stack([(slabs + 0.5) * SLAB, np.zeros(len(slabs)), np.zeros(len(slabs))])


def test_a_tapering_blade_as_thick_as_the_handle_is_cut_at_the_handle_even_run() -> None:
    blade = np.linspace(0.003, 0.018, 50)  # tapers to a point, through the handle's width
    width = [*blade, *[0.014] * 50]  # a 10 cm handle 14 mm wide at the tool's far end
    profile = _profile([0.006] * 100, width)
    assert even_run(profile, (0, 99), CONFIG) == (50, 99, False)
    every = _at(np.arange(100))
    keep = handle_span(every, every, profile, CONFIG)
    assert keep[50:].all() and not keep[:45].any()
    half = _at(np.arange(60, 100))  # a region on the handle only: nothing to cut
    assert handle_span(every, half, profile, CONFIG).all()
    assert handle_span(every, every, profile, CrossSectionConfig()).all()  # off by default


def test_a_bolster_before_a_thin_blade_is_cut_a_bar_between_heads_is_not() -> None:
    config = replace(CONFIG, bolster_reach=0.02)
    thickness = [0.0015] * 40 + [0.021] * 5 + [0.018] * 50  # blade, bolster, handle
    width = [0.03] * 40 + [0.025] * 5 + [0.021] * 50
    profile = _profile(thickness, width)
    region = _at(np.arange(40, 95))  # the handle and the bolster
    assert handle_span(_at(np.arange(95)), region, profile, CONFIG).all()  # off unless asked
    keep = handle_span(_at(np.arange(95)), region, profile, config)
    assert keep[45:].all() and not keep[40:45].any()
    heads = [0.02] * 10 + [0.008] * 60 + [0.02] * 10  # a wrench: no blade, no end run
    bar = _profile(heads, [0.04] * 10 + [0.012] * 60 + [0.04] * 10)
    assert handle_span(_at(np.arange(80)), _at(np.arange(5, 75)), bar, config).all()
