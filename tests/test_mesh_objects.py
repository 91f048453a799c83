"""Objects from any mesh file: units, bad meshes, the catalog, handle files."""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
import trimesh

from simgrasp.assets.mesh_object import with_options
from simgrasp.assets.registry import load_object
from simgrasp.errors import SimgraspError

BOX_M = (0.04, 0.06, 0.10)


def _box_file(path: Path, factor: float = 1.0) -> Path:
    box = trimesh.creation.box(BOX_M)
    box.apply_scale(factor)
    box.export(path)
    return path


def test_mesh_in_millimetres_fails_then_loads_with_units(tmp_path: Path) -> None:
    path = _box_file(tmp_path / "box_mm.stl", 1000.0)
    with pytest.raises(SimgraspError, match="units=mm") as refused:  # a Python caller's spelling
        load_object(str(path))
    assert "--units" not in str(refused.value)
    asset = load_object(with_options(str(path), units="mm", mass=0.2))
    assert np.allclose(asset.mesh.extents, BOX_M)
    assert asset.mass == pytest.approx(0.2)
    density = load_object(with_options(str(path), scale=0.001, density=1000.0))
    assert density.mass == pytest.approx(1000.0 * np.prod(BOX_M), rel=1e-6)


def test_a_file_name_holding_a_question_mark_is_a_path(tmp_path: Path) -> None:
    """``?`` starts a spec's options, but a name ending in a mesh suffix is all path; options
    after such a name still parse."""
    path = _box_file(tmp_path / "odd?name.stl", 1000.0)
    assert np.allclose(load_object(str(path) + "?units=mm").mesh.extents, BOX_M)
    with pytest.raises(SimgraspError, match="odd\\?name.stl"):
        load_object(str(path))


def test_mesh_in_millimetres_on_the_command_line(tmp_path: Path) -> None:
    """One line, exit code 2, naming the file and the fix."""
    path = _box_file(tmp_path / "box_mm.stl", 1000.0)
    grasps = tmp_path / "g.npz"
    np.savez(grasps, object_T_grasp=np.eye(4)[None])
    env = {**os.environ, "PYTHONPATH": str(Path(__file__).parents[1])}
    command = [sys.executable, "-m", "simgrasp", "label-grasps", str(path), "--grasps", str(grasps)]
    done = subprocess.run(command, capture_output=True, text=True, env=env, cwd=tmp_path)
    assert done.returncode == 2
    assert len(done.stderr.strip().splitlines()) == 1
    assert "box_mm.stl" in done.stderr and "--units mm" in done.stderr


def test_non_watertight_mesh_loads_with_hull_mass(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    box = trimesh.creation.box(BOX_M)
    open_box = trimesh.Trimesh(box.vertices, box.faces[2:], process=False)
    assert not open_box.is_watertight
    open_box.export(tmp_path / "open.obj")
    asset = load_object(str(tmp_path / "open.obj") + "?density=1000")
    assert "not watertight" in capsys.readouterr().err
    assert asset.mass == pytest.approx(1000.0 * np.prod(BOX_M), rel=1e-6)  # hull volume
    assert not asset.mesh.is_watertight


@pytest.mark.parametrize(
    ("make", "message"),
    [
        (lambda p: p.write_text(""), "no triangles|cannot read"),
        (
            lambda p: trimesh.Trimesh(
                [[0.0, 0.0, 0.0], [0.1, 0.0, 0.0], [0.0, 0.1, 0.0], [0.1, 0.1, 0.0]],
                [[0, 1, 2], [1, 3, 2]],
            ).export(p),
            "zero volume",
        ),
    ],
    ids=["empty", "flat"],
)
def test_bad_meshes_fail_with_one_line(tmp_path: Path, make, message: str) -> None:
    path = tmp_path / "bad.obj"
    make(path)
    with pytest.raises(SimgraspError, match=message):
        load_object(str(path))


def test_too_many_loose_parts(tmp_path: Path) -> None:
    grid = np.stack(np.meshgrid(*[np.arange(11)] * 3), -1).reshape(-1, 3)[:1001] * 0.003
    parts = [trimesh.creation.box((0.002, 0.002, 0.002)).apply_translation(p) for p in grid]
    trimesh.util.concatenate(parts).export(tmp_path / "soup.stl")
    with pytest.raises(SimgraspError, match="1001 loose parts"):
        load_object(str(tmp_path / "soup.stl"))


def test_catalog_and_handle_file(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    _box_file(tmp_path / "crate.stl", 100.0)  # in cm
    handles = {
        "objects": {
            "crate": {
                "regions": [
                    {"type": "box", "center": [0, 0, 0.04], "half_extents": [0.03, 0.04, 0.02]}
                ]
            }
        }
    }
    (tmp_path / "handles.json").write_text(json.dumps(handles))
    (tmp_path / "objects.toml").write_text(
        '[my_crate]\nmesh = "crate.stl"\nunits = "cm"\nmass = 0.5\nfriction = 0.6\n'
        'handles = "handles.json"\n'
    )
    monkeypatch.setenv("SIMGRASP_OBJECTS", str(tmp_path / "objects.toml"))
    asset = load_object("my_crate")
    assert np.allclose(asset.mesh.extents, BOX_M)
    assert (asset.mass, asset.friction) == (0.5, 0.6)
    assert asset.handle.contains([[0, 0, 0.045], [0, 0, -0.045]]).tolist() == [True, False]
    assert asset.handle_source == "file"


@pytest.mark.parametrize(
    ("entry", "message"),
    [
        ("mesh = 3", "mesh must be text, got 3"),
        ('mesh = "crate.stl"\nmass = "heavy"', "mass must be a number, got 'heavy'"),
        ('mesh = "crate.stl"\nfriction = true', "friction must be a number, got True"),
        ('mesh = "crate.stl"\nunits = 10', "units must be text, got 10"),
    ],
)
def test_a_catalog_value_of_the_wrong_type_is_one_line(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, entry: str, message: str
) -> None:
    (tmp_path / "objects.toml").write_text(f"[crate]\n{entry}\n")
    monkeypatch.setenv("SIMGRASP_OBJECTS", str(tmp_path / "objects.toml"))
    with pytest.raises(SimgraspError, match=f"\\[crate\\] {message}"):
        load_object("crate")


def test_a_mesh_without_handle_file_gets_the_automatic_label_cached(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture
) -> None:
    """No ``handles``: the label ``label-handles`` finds (a generated mug's strap), kept in the
    cache and read back from it the second time; a YCB object's label is the shipped one."""
    from simgrasp.assets.auto_handles import automatic_handle_label
    from simgrasp.assets.cache import cache_dir
    from simgrasp.assets.generated import generate_tool
    from simgrasp.perception import sample_surface

    monkeypatch.setenv("SIMGRASP_CACHE_DIR", str(tmp_path / "cache"))
    mug = generate_tool("mug", 0)
    path = tmp_path / "mug.stl"
    mug.mesh.export(path)
    asset = load_object(str(path))
    assert asset.handle_source == "automatic" and asset.handle.regions
    note = capsys.readouterr().err.strip().splitlines()
    assert len(note) == 1 and "has no handle file" in note[0] and "mug.stl" in note[0]
    points, _ = sample_surface(mug.mesh, 20000, np.random.default_rng(0))
    found, exact = asset.handle.contains(points), mug.handle.contains(points)
    # the handle beyond the wall's margin (its roots are the wall's), and nothing of the body
    both = (found & exact).sum()
    assert both / exact.sum() >= 0.75 and both / found.sum() >= 0.95
    (entry,) = cache_dir("handle-labels").glob("*.json")
    stamp = entry.stat().st_mtime_ns
    again = automatic_handle_label(asset.mesh, "again")
    assert entry.stat().st_mtime_ns == stamp and again.object_name == "again"
    assert capsys.readouterr().err == ""  # read from the cache: nothing computed, no note
    assert np.array_equal(again.contains(points), found)
    entry.write_text("not json")  # a damaged entry is rebuilt, not an error
    assert np.array_equal(automatic_handle_label(asset.mesh, "x").contains(points), found)
    assert json.loads(entry.read_text())["objects"]
    assert load_object("gen_mug_s0").handle_source == "shipped"


def _simgrasp(*args: str, cwd: Path) -> subprocess.CompletedProcess[str]:
    env = {**os.environ, "PYTHONPATH": str(Path(__file__).parents[1])}
    command = [sys.executable, "-m", "simgrasp", *args]
    return subprocess.run(command, capture_output=True, text=True, env=env, cwd=cwd)


def test_trial_of_a_mesh_in_millimetres_needs_units_then_runs(tmp_path: Path) -> None:
    """``trial`` takes the mesh flags of label-grasps: the millimetre box fails with one line
    suggesting --units/--scale, then ``--units mm --mass 0.2`` runs its trial."""
    path = _box_file(tmp_path / "box_mm.stl", 1000.0)
    grasp = ["--grasp-frame", "object", "--grasp", "0", "0", "0.03", "0", "1", "0", "0"]
    refused = _simgrasp("trial", str(path), *grasp, cwd=tmp_path)
    assert refused.returncode == 2
    assert len(refused.stderr.strip().splitlines()) == 1
    assert "box_mm.stl" in refused.stderr and "--units mm" in refused.stderr
    assert "--scale 0.001" in refused.stderr
    done = _simgrasp("trial", str(path), "--units", "mm", "--mass", "0.2", "--json", *grasp,
                     cwd=tmp_path)  # fmt: skip
    assert done.returncode == 0, done.stderr
    record = json.loads(done.stdout)
    assert record["object"] == f"{path}?units=mm&mass=0.2"
    assert record["failure"] != "no_grasp"
    assert record["handle_source"] == "automatic"  # a box: its automatic label is empty
    assert record["on_handle"] is False


@pytest.mark.parametrize(
    ("flag", "args"),
    [
        ("--scale", ["trial", "gen_hammer", "--scale", "2"]),
        ("--friction", ["evaluate", "--objects", "gen_hammer", "--friction", "0.5", "--out", "o"]),
    ],
)
def test_mesh_flags_on_a_named_object_fail_with_one_line(
    tmp_path: Path, flag: str, args: list[str]
) -> None:
    """A mesh flag on a generated tool (no mesh file to read): one line naming both, exit 2."""
    done = _simgrasp(*args, cwd=tmp_path)
    assert done.returncode == 2
    assert done.stderr.strip().splitlines() == [
        f"simgrasp {args[0]}: error: {flag} only applies to a mesh file object, not 'gen_hammer'"
    ]
    assert not (tmp_path / "o").exists()
