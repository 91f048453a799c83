"""CoACD decomposition cache: reuse, corruption recovery, concurrent builders."""

from __future__ import annotations

import multiprocessing
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from simgrasp.assets import cache, decompose
from simgrasp.assets.decompose import DecompositionConfig
from simgrasp.assets.generated import generate_tool

CONFIG = DecompositionConfig(preprocess_mode="off")


@pytest.fixture
def cache_dir(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> Path:
    monkeypatch.setenv(cache.CACHE_ENV, str(tmp_path))
    return tmp_path / "decompositions"


def _entries(directory: Path) -> list[Path]:
    return sorted(directory.glob("*.npz"))


def test_second_build_makes_no_coacd_call(cache_dir: Path) -> None:
    mesh = generate_tool("hammer", 3).mesh
    first = decompose.decompose(mesh, CONFIG, "gen_hammer_s3")
    calls = decompose.coacd_calls()
    second = decompose.decompose(mesh, CONFIG, "gen_hammer_s3")
    assert decompose.coacd_calls() == calls
    assert len(_entries(cache_dir)) == 1
    assert len(first) == len(second)
    for a, b in zip(first, second, strict=True):
        assert np.array_equal(a.vertices, b.vertices)
    # a different config is a different entry
    decompose.decompose(mesh, DecompositionConfig(preprocess_mode="off", threshold=0.2), "h")
    assert decompose.coacd_calls() == calls + 1


@pytest.mark.parametrize("damage", ["truncate", "flip_bytes", "garbage"])
def test_corrupt_entry_is_detected_and_rebuilt(
    cache_dir: Path, damage: str, caplog: pytest.LogCaptureFixture
) -> None:
    mesh = generate_tool("screwdriver", 1).mesh
    reference = decompose.decompose(mesh, CONFIG, "gen_screwdriver_s1")
    (entry,) = _entries(cache_dir)
    data = entry.read_bytes()
    if damage == "truncate":
        entry.write_bytes(data[: len(data) // 2])
    elif damage == "flip_bytes":
        # the vertex block sits early in the zip (stored, not compressed): corrupt its payload
        middle = bytearray(data)
        for i in range(len(middle) // 3, len(middle) // 3 + 64):
            middle[i] ^= 0xFF
        entry.write_bytes(bytes(middle))
    else:
        entry.write_bytes(b"not an npz file")
    calls = decompose.coacd_calls()
    with caplog.at_level("WARNING", logger="simgrasp.assets.cache"):
        rebuilt = decompose.decompose(mesh, CONFIG, "gen_screwdriver_s1")
    assert decompose.coacd_calls() == calls + 1
    assert "corrupt" in caplog.text
    assert len(rebuilt) == len(reference)
    assert cache.load_hulls(entry) is not None


def _build_in_child(cache_root: str, queue: multiprocessing.Queue) -> None:
    import os

    os.environ[cache.CACHE_ENV] = cache_root
    hulls = decompose.decompose(generate_tool("mug", 4).mesh, CONFIG, "gen_mug_s4")
    queue.put(len(hulls))


def test_two_processes_building_at_once_both_succeed(cache_dir: Path) -> None:
    context = multiprocessing.get_context("spawn")
    queue = context.Queue()
    workers = [
        context.Process(target=_build_in_child, args=(str(cache_dir.parent), queue))
        for _ in range(2)
    ]
    for worker in workers:
        worker.start()
    for worker in workers:
        worker.join(timeout=120)
        assert worker.exitcode == 0
    counts = [queue.get(timeout=5), queue.get(timeout=5)]
    assert counts[0] == counts[1] > 1
    (entry,) = _entries(cache_dir)
    assert not list(cache_dir.glob("*.tmp"))
    hulls = cache.load_hulls(entry)
    assert hulls is not None and len(hulls) == counts[0]


def test_bad_inputs_name_the_problem() -> None:
    with pytest.raises(ValueError, match="threshold"):
        DecompositionConfig(threshold=5.0)
    mesh = generate_tool("can", 0).mesh.copy()
    mesh.vertices[0] = np.nan
    with pytest.raises(ValueError, match="gen_can_s0.*non-finite"):
        decompose.run_coacd(mesh, CONFIG, "gen_can_s0")


def test_a_directory_at_an_entry_path_is_a_clear_error(cache_dir: Path) -> None:
    mesh = generate_tool("hammer", 3).mesh
    path = cache.entry_path(cache.cache_key(mesh, CONFIG.coacd_params()))
    path.mkdir(parents=True)
    with pytest.raises(ValueError, match=rf"{path} is a directory.*remove it"):
        decompose.decompose(mesh, CONFIG, "gen_hammer_s3")
    assert path.is_dir()


def test_a_cache_dir_variable_naming_a_file_is_a_clear_error(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    not_a_dir = tmp_path / "cache.txt"
    not_a_dir.write_text("x")
    monkeypatch.setenv(cache.CACHE_ENV, str(not_a_dir))
    with pytest.raises(ValueError, match=rf"SIMGRASP_CACHE_DIR={not_a_dir}.*not a directory"):
        decompose.decompose(generate_tool("hammer", 3).mesh, CONFIG, "gen_hammer_s3")


def test_open3d_imports_after_a_coacd_run() -> None:
    """A script that decomposes first and scans (Open3D) second must not crash on import:
    loading coacd's library before scipy.spatial makes ``import open3d`` raise std::bad_cast."""
    script = (
        "import simgrasp.assets.decompose as d, trimesh\n"
        "d.run_coacd(trimesh.creation.box((0.1, 0.05, 0.02)), d.DecompositionConfig(), 'box')\n"
        "import open3d\n"
    )
    result = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True)
    assert result.returncode == 0, result.stderr[-500:]
