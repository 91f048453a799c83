"""``simgrasp bench export``: every scene of a suite as the folder a method outside simgrasp
reads (``DIR/SCENE/observation.json``, :mod:`simgrasp.bench.observation`).

``DIR/suite.json`` names the suite, its digest and its scenes in order; a folder exported
from another definition is refused. A scene whose ``observation.json`` exists is finished
(that file is written last), so a killed export resumes with the rest.
"""

from __future__ import annotations

from pathlib import Path

from simgrasp.bench.observation import write_observation
from simgrasp.bench.scene_build import build_bench_scene, observe_bench_scene
from simgrasp.bench.suites import SuiteDefinition, check_suite_data
from simgrasp.runs.engine import RunConfig, Work, run_tasks
from simgrasp.runs.identity import claim_identity
from simgrasp.runs.out_dir import claim_out_dir


def export_scene(scene_id: str, suite: SuiteDefinition, out: str) -> str:
    """Write scene ``scene_id``'s observation folder under ``out``; returns the id."""
    scene = suite.scene(scene_id)
    built = build_bench_scene(suite, scene)
    write_observation(observe_bench_scene(suite, scene, built), Path(out) / scene.id)
    return scene.id


def export_suite(
    suite: SuiteDefinition, out: Path, run: RunConfig, command: list[str]
) -> list[str]:
    """Export every scene of ``suite`` not yet in ``out``; returns the ids exported now."""
    from tqdm import tqdm

    check_suite_data(suite)
    scenes = suite.scenes()
    with claim_out_dir(out, command):
        identity = {
            "suite": suite.name,
            "suite_sha256": suite.digest(),
            "scenes": [s.id for s in scenes],
        }
        claim_identity(out / "suite.json", identity, what="an export of another suite")
        todo = [s.id for s in scenes if not (out / s.id / "observation.json").is_file()]
        done = []
        work = Work(export_scene, (suite, str(out)))
        bar = tqdm(total=len(scenes), initial=len(scenes) - len(todo), disable=not run.progress)
        with bar:
            for scene_id in run_tasks(work, todo, run):
                done.append(scene_id)
                bar.update()
    return done
