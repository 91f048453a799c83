"""Grasp-evaluation sweeps: every object x detector x gripper x noise x seed as one full-chain
trial (:func:`simgrasp.grasping.chain.run_chain`), run in worker processes or as Ray tasks and
recorded in a resumable :class:`~simgrasp.evaluation.trial_log.TrialLog`.

Workers are started with the ``spawn`` method (a GL context must not cross a ``fork``); each
worker builds every object model once (CoACD decompositions come from the on-disk cache).
"""

from __future__ import annotations

import functools
import itertools
import os
from collections.abc import Callable, Generator, Iterable, Iterator, Sequence
from concurrent.futures import FIRST_COMPLETED, wait
from contextlib import closing
from dataclasses import asdict, dataclass
from pathlib import Path
from typing import Any, Literal, cast

from simgrasp.assets.placement import DEFAULT_PLACEMENT, Placement
from simgrasp.evaluation.trial_log import NOISE_DIGITS, TrialKey, TrialLog, trial_key
from simgrasp.process_pool import spawn_pool
from simgrasp.scenes.views import CHAIN_VIEWS

Backend = Literal["local", "ray"]
TRIALS_FILE = "trials.jsonl"


@dataclass(frozen=True, order=True)
class TrialSpec:
    """One trial of a sweep; ``noise`` is the chain's multiplicative cloud-noise sigma,
    ``placement`` the scene's (:class:`simgrasp.scenes.scene.SceneConfig`) and ``views`` its
    number of cameras."""

    object: str
    detector: str
    gripper: str
    noise: float
    seed: int
    placement: Placement = DEFAULT_PLACEMENT
    views: int = CHAIN_VIEWS

    @property
    def key(self) -> TrialKey:
        return trial_key(asdict(self))


def plan_trials(
    objects: Sequence[str],
    detectors: Sequence[str],
    grippers: Sequence[str],
    noises: Sequence[float],
    seeds: Iterable[int],
    placement: Placement = DEFAULT_PLACEMENT,
    views: int = CHAIN_VIEWS,
) -> list[TrialSpec]:
    """Every combination, object-major (so workers share decomposed models early), each
    object placed by ``placement`` and seen by ``views`` cameras."""
    return [
        TrialSpec(obj, det, grip, round(float(noise), NOISE_DIGITS), int(seed), placement, views)
        for obj, det, grip, noise, seed in itertools.product(
            objects, detectors, grippers, noises, list(seeds)
        )
    ]


@functools.cache
def _object_model(name: str, ycb_dir: str | None):  # -> ObjectModel (lazy mujoco import)
    from simgrasp.grasping.chain import model_for

    return model_for(name, ycb_dir)


def prepare_object(name: str, ycb_dir: str | None) -> str:
    """Build (or load from the cache) the model of ``name`` in this process; returns the name."""
    _object_model(name, ycb_dir)
    return name


def run_spec(spec: TrialSpec, ycb_dir: str | None) -> dict[str, Any]:
    """Run one full-chain trial; the flat chain record with the spec's key fields."""
    from simgrasp.grasping.chain import ChainConfig, ChainDetector, run_chain

    config = (
        ChainConfig(
            detector=cast(ChainDetector, spec.detector), gripper=spec.gripper, noise=spec.noise
        )
        .with_placement(spec.placement)
        .with_views(spec.views)
    )
    record = run_chain(_object_model(spec.object, ycb_dir), config, spec.seed).to_json()
    record["object_asset"] = record["object"]
    record.update(asdict(spec))
    return record


def run_local(
    specs: Sequence[TrialSpec], ycb_dir: str | None, workers: int
) -> Iterator[dict[str, Any]]:
    """Yield trial records as they finish (in completion order) from ``workers`` spawned
    processes; ``workers <= 1`` runs in this process."""
    objects = list(dict.fromkeys(s.object for s in specs))
    if workers <= 1:
        for name in objects:
            prepare_object(name, ycb_dir)
        yield from (run_spec(spec, ycb_dir) for spec in specs)
        return
    pool = spawn_pool(workers)
    try:
        list(pool.map(prepare_object, objects, itertools.repeat(ycb_dir)))
        pending = {pool.submit(run_spec, spec, ycb_dir) for spec in specs}
        while pending:
            done, pending = wait(pending, return_when=FIRST_COMPLETED)
            for future in done:
                yield future.result()
    finally:  # on an error, drop the queued trials instead of running them all first
        pool.shutdown(cancel_futures=True)


def run_ray(
    specs: Sequence[TrialSpec], ycb_dir: str | None, workers: int, address: str | None
) -> Iterator[dict[str, Any]]:
    """Yield trial records as Ray tasks finish. Without ``address`` a new local Ray instance
    with ``workers`` CPUs is started (and shut down afterwards), even if ``RAY_ADDRESS`` is set
    or a ``ray start`` cluster runs on this machine; ``address="auto"`` joins those."""
    try:
        import ray
    except ImportError:
        raise ValueError(
            "--backend ray needs Ray: install the extra with `pip install 'simgrasp[ray]'` "
            "(or `pip install 'ray[default]'`)"
        ) from None
    started = not ray.is_initialized()
    if started:
        env = {k: v for k, v in os.environ.items() if k.startswith(("SIMGRASP_", "MUJOCO_"))}
        ray.init(
            address=address or "local",
            num_cpus=None if address else workers,
            include_dashboard=False,
            log_to_driver=False,
            runtime_env={"env_vars": env},
        )
    try:
        prepare = ray.remote(prepare_object)
        ray.get([prepare.remote(name, ycb_dir) for name in dict.fromkeys(s.object for s in specs)])
        remote = ray.remote(run_spec)
        pending = [remote.remote(spec, ycb_dir) for spec in specs]
        while pending:
            done, pending = ray.wait(pending, num_returns=1)
            yield from ray.get(done)
    finally:
        if started:
            ray.shutdown()


def run_trials(
    specs: Sequence[TrialSpec],
    ycb_dir: str | None,
    workers: int,
    backend: Backend,
    address: str | None,
) -> Generator[dict[str, Any], None, None]:
    """Trial records from ``backend``, in completion order; starts no workers (nor Ray) when
    there is nothing to run."""
    if backend not in ("local", "ray"):
        raise ValueError(f"unknown backend {backend!r}; use 'local' or 'ray'")
    if specs:
        yield from (
            run_ray(specs, ycb_dir, workers, address)
            if backend == "ray"
            else run_local(specs, ycb_dir, workers)
        )


def run_sweep(
    specs: Sequence[TrialSpec],
    out_dir: Path,
    *,
    ycb_dir: str | None = None,
    workers: int = 1,
    backend: Backend = "local",
    address: str | None = None,
    progress: bool = True,
    on_record: Callable[[dict[str, Any]], None] | None = None,
) -> list[dict[str, Any]]:
    """Run the trials of ``specs`` not yet in ``out_dir/trials.jsonl``, appending each as it
    finishes; return the records of all of ``specs`` (earlier and new), in ``specs`` order."""
    from tqdm import tqdm

    if len(set(s.key for s in specs)) != len(specs):
        raise ValueError("the sweep plan lists a trial twice")
    log = TrialLog(Path(out_dir) / TRIALS_FILE)
    wanted = {spec.key for spec in specs}
    finished = {trial_key(r): r for r in log.load() if trial_key(r) in wanted}
    todo = [spec for spec in specs if spec.key not in finished]
    bar = tqdm(
        total=len(specs), initial=len(finished), desc="evaluate", unit="trial", disable=not progress
    )
    with closing(run_trials(todo, ycb_dir, workers, backend, address)) as records:
        for record in records:
            key = trial_key(record)
            if key in finished:  # never record a trial twice
                continue
            log.append(record)
            finished[key] = record
            bar.update()
            if on_record:
                on_record(record)
    bar.close()
    return [finished[spec.key] for spec in specs]
