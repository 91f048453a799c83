"""The thickness profile of long tools (simgrasp.autolabel.cross_section) on meshes whose
answer is known: a knife with a round handle, a guard and a thin blade; a spanner's flat bar
between heads; a cup."""

from __future__ import annotations

from typing import cast

import numpy as np
import pytest
import trimesh

from simgrasp.autolabel.cross_section import (
    CrossSectionConfig,
    alike_share,
    long_runs,
    off_head,
    section_profile,
    section_run,
    thick_enough,
)

CONFIG = CrossSectionConfig()
TURN = trimesh.transformations.rotation_matrix(0.9, [1.0, -0.5, 0.3])
"""The test knife is turned off the axes: the profile must find its long axis itself."""


def _knife_points() -> tuple[np.ndarray, np.ndarray]:
    """Points (m) on a knife turned by :data:`TURN`: a round handle (radius 9 mm, local z -0.05
    to 0.05), a guard at z 0.05-0.056 and a blade 30 mm wide, 2 mm thick up to z 0.146; and
    each point's local z."""
    handle = trimesh.creation.cylinder(radius=0.009, height=0.10, sections=48)
    guard = trimesh.creation.box([0.036, 0.010, 0.006])
    guard.apply_translation([0.0, 0.0, 0.053])
    blade = trimesh.creation.box([0.030, 0.002, 0.09])
    blade.apply_translation([0.0, 0.0, 0.101])
    knife = cast(trimesh.Trimesh, trimesh.util.concatenate([handle, guard, blade]))
    local, _ = trimesh.sample.sample_surface(knife, 40000, seed=0)
    local = np.asarray(local)
    return local @ TURN[:3, :3].T, local[:, 2]


def test_a_knife_blade_is_thin_and_leaves_the_handle_region() -> None:
    points, z = _knife_points()
    profile = section_profile(points, CONFIG)
    assert profile is not None
    thickness = profile.thickness[profile.slabs_of(points)]
    handle, blade = np.abs(z) < 0.045, z > 0.066
    assert np.all((thickness[handle] > 0.015) & (thickness[handle] < 0.02))  # 18 mm across
    assert np.all(thickness[blade] < 0.003)  # 2 mm
    keep = thick_enough(points, points[handle][::50], profile, CONFIG)
    assert keep[handle].all() and not keep[blade].any()
    off = thick_enough(points, points[blade][::50], profile, CONFIG)  # found on the blade
    assert off[blade].all()


def test_a_cup_is_not_elongated() -> None:
    cup = trimesh.creation.cylinder(radius=0.04, height=0.10, sections=64)
    points, _ = trimesh.sample.sample_surface(cup, 20000, seed=0)
    assert section_profile(np.asarray(points), CONFIG) is None


def test_a_handle_found_in_part_runs_on_to_its_end_and_stops_at_the_guard() -> None:
    points, z = _knife_points()
    profile = section_profile(points, CONFIG)
    assert profile is not None
    middle = points[np.abs(z) < 0.01][::50]  # candidates on the middle fifth of the handle
    run = section_run(points, middle, profile, CONFIG)
    handle, guard_or_blade = np.abs(z) < 0.048, z > 0.052
    assert run[handle].mean() > 0.99 and not run[guard_or_blade].any()
    on_blade = section_run(points, points[z > 0.09][::50], profile, CONFIG)
    assert not on_blade.any()  # a part on the thinner end does not grow
    # the guard (36 mm wide, 6 mm long) is twice the handle's width: a looser ratio takes it
    loose = section_run(points, middle, profile, CrossSectionConfig(grow_ratio=2.5))
    guard = (z > 0.052) & (z < 0.054)
    assert loose[guard].all() and not loose[z > 0.066].any()


def test_the_share_alike_a_part_is_its_handle_on_a_knife_and_all_of_a_bar() -> None:
    points, z = _knife_points()
    profile = section_profile(points, CONFIG)
    assert profile is not None
    middle = points[np.abs(z) < 0.01][::50]
    handle_share = float((np.abs(z) < 0.05).mean())  # the handle's share of the surface
    assert alike_share(points, middle, profile, CONFIG) == pytest.approx(handle_share, abs=0.03)
    bar = trimesh.creation.box([0.3, 0.03, 0.004])
    bar_points = np.asarray(trimesh.sample.sample_surface(bar, 20000, seed=0)[0])
    bar_profile = section_profile(bar_points, CONFIG)
    assert bar_profile is not None
    assert alike_share(bar_points, bar_points[::100], bar_profile, CONFIG) > 0.95
    assert np.isnan(
        alike_share(bar_points, bar_points[::100], bar_profile, CrossSectionConfig(grow_ratio=0))
    )


def test_a_head_wider_and_thicker_than_the_bar_leaves_the_region_a_plate_does_not() -> None:
    """A flat bar (14 x 6 mm, local z -0.06 to 0.06) with a head 30 x 9 mm at one end and a
    plate 60 x 2 mm at the other: the head grows both ways and is left out, the plate only
    widens and stays (a spatula's plate is left out by its thinness, not here)."""
    bar = trimesh.creation.box([0.014, 0.006, 0.12])
    head = trimesh.creation.box([0.030, 0.009, 0.03])
    head.apply_translation([0.0, 0.0, -0.075])
    plate = trimesh.creation.box([0.060, 0.002, 0.05])
    plate.apply_translation([0.0, 0.0, 0.085])
    tool = cast(trimesh.Trimesh, trimesh.util.concatenate([bar, head, plate]))
    local = np.asarray(trimesh.sample.sample_surface(tool, 40000, seed=0)[0])
    points, z = local @ TURN[:3, :3].T, local[:, 2]
    profile = section_profile(points, CONFIG)
    assert profile is not None
    middle = points[np.abs(z) < 0.03][::50]
    config = CrossSectionConfig(head_width_ratio=1.2)
    keep = off_head(points, middle, profile, config)
    assert keep[np.abs(z) < 0.055].all() and not keep[z < -0.065].any()
    assert keep[z > 0.065].all()
    assert off_head(points, middle, profile, CrossSectionConfig(head_width_ratio=0.0)).all()


def test_a_part_whose_section_runs_a_few_millimetres_is_dropped_beside_a_handle() -> None:
    """Parts found on the handle's middle (its even section runs 100 mm) and on the guard
    (6 mm): the guard's part is dropped; alone, or with the test off, every part is kept."""
    points, z = _knife_points()
    profile = section_profile(points, CONFIG)
    assert profile is not None
    handle = points[np.abs(z) < 0.01][::50]
    guard = points[(z > 0.051) & (z < 0.055)][::20]
    config = CrossSectionConfig(min_run=0.03)
    assert long_runs([handle, guard], profile, config) == [True, False]
    assert long_runs([guard], profile, config) == [True]  # no part runs long: all kept
    assert long_runs([handle, guard], profile, CrossSectionConfig(min_run=0.0)) == [True, True]
    assert long_runs([handle, guard], None, config) == [True, True]  # not a long tool
    no_alike = CrossSectionConfig(min_run=0.03, grow_ratio=0.0)
    assert long_runs([handle, guard], profile, no_alike) == [True, True]


def test_a_bar_between_short_thick_heads_grows_though_thinner_than_the_tool_median() -> None:
    """A wrench-like bar: 6 mm thick in its middle, 6.6 mm toward its ends (the tool's median
    slab), heads 9 mm thick but 2.5 cm long. A part found in the middle is thinner than the
    tool's median, yet it is on no blade (nothing thicker runs 3 cm): it grows over the bar
    and stops at the heads (the guard before this compared with the tool's median slab)."""
    pieces = [trimesh.creation.box([0.014, 0.006, 0.06])]
    for sign in (-1.0, 1.0):
        end = trimesh.creation.box([0.014, 0.0066, 0.04])
        end.apply_translation([0.0, 0.0, sign * 0.05])
        head = trimesh.creation.box([0.030, 0.009, 0.025])
        head.apply_translation([0.0, 0.0, sign * 0.0825])
        pieces += [end, head]
    tool = cast(trimesh.Trimesh, trimesh.util.concatenate(pieces))
    local = np.asarray(trimesh.sample.sample_surface(tool, 60000, seed=0)[0])
    points, z = local @ TURN[:3, :3].T, local[:, 2]
    profile = section_profile(points, CONFIG)
    assert profile is not None
    middle = points[np.abs(z) < 0.01][::50]
    assert profile.median_of(profile.slabs_of(middle))[0] < np.nanmedian(profile.thickness)
    run = section_run(points, middle, profile, CONFIG)
    assert run[np.abs(z) < 0.066].mean() > 0.99 and not run[np.abs(z) > 0.074].any()
