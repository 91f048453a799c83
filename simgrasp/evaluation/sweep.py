"""Grasp-evaluation sweeps: every object x swept settings x seed as one full-chain
trial (:func:`simgrasp.grasping.trials.chain.run_chain`), run by the resumable-run engine
(:mod:`simgrasp.runs`) in worker processes or as Ray tasks and recorded in ``trials.jsonl``.

Workers are started with the ``spawn`` method (a GL context must not cross a ``fork``); each
worker process runs its trials in one :class:`~simgrasp.grasping.session.Session` (its
renderer and object models: every object model built once, CoACD decompositions from the
on-disk cache), which the worker's exit frees; a sweep run in this process closes it at its end.
"""

from __future__ import annotations

import functools
import itertools
from collections.abc import Callable, Iterable, Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from simgrasp.config.tree import build
from simgrasp.evaluation.trial_log import (
    NOISE_DIGITS,
    TrialKey,
    check_defaults,
    check_meshes,
    trial_key,
    trial_log,
    trial_settings,
)
from simgrasp.grasping.trials.chain_config import ChainConfig
from simgrasp.runs.engine import Backend, RunConfig, Work, run_resumable, run_tasks

TRIALS_FILE = "trials.jsonl"
SWEEP_AXES = ("detector.kind", "gripper", "noise")
"""The chain settings a sweep varies (in this order, inside the object and outside the seed)."""


@dataclass(frozen=True)
class TrialSpec:
    """One trial of a sweep: an object, a seed and the chain's settings."""

    object: str
    seed: int
    config: ChainConfig

    @property
    def settings(self) -> dict[str, Any]:
        """How ``config`` differs from the default chain config (the trial's identity)."""
        return trial_settings(self.config)

    @functools.cached_property
    def key(self) -> TrialKey:
        """(object, seed, settings): computed once, a sweep looks it up several times."""
        return trial_key({"object": self.object, "seed": self.seed, "settings": self.settings})

    def summary_fields(self) -> dict[str, Any]:
        """The record fields that name the trial for reports (object, detector, gripper,
        noise, seed, placement, views, sensor) and its ``settings``."""
        config = self.config
        return {
            "object": self.object,
            "detector": config.detector.kind,
            "gripper": config.gripper,
            "noise": config.noise,
            "seed": self.seed,
            "placement": config.scene.placement,
            "views": config.scene.num_views,
            "sensor": config.sensor.kind,
            "settings": self.settings,
        }


def plan_trials(
    objects: Sequence[str],
    axes: Mapping[str, Sequence[Any]],
    seeds: Iterable[int],
    base: ChainConfig | None = None,
) -> list[TrialSpec]:
    """Every object x axis values x seed, object-major (so workers share decomposed models
    early); ``axes`` maps dotted chain settings (e.g. ``detector.kind``) to the values swept,
    applied to ``base`` (default: the default chain config)."""
    base = base or ChainConfig()
    axes = {k: [round(float(v), NOISE_DIGITS) for v in vs] if k == "noise" else vs
            for k, vs in axes.items()}  # fmt: skip
    keys = list(axes)
    configs = [
        build(ChainConfig, dict(zip(keys, values, strict=True)), base=base)
        for values in itertools.product(*(axes[key] for key in keys))
    ]
    seeds = list(seeds)
    return [
        TrialSpec(obj, int(seed), config) for obj in objects for config in configs for seed in seeds
    ]


def prepare_object(name: str, ycb_dir: str | None) -> str:
    """Build (or load from the cache) the model of ``name`` in this process; returns the name."""
    from simgrasp.grasping.session import worker_session

    worker_session(ycb_dir).model(name)
    return name


def run_spec(spec: TrialSpec, ycb_dir: str | None) -> dict[str, Any]:
    """Run one full-chain trial; the flat chain record with the spec's summary fields."""
    from simgrasp.grasping.session import worker_session
    from simgrasp.grasping.trials.chain import run_chain

    session = worker_session(ycb_dir)
    result = run_chain(session.model(spec.object), spec.config, spec.seed, session=session)
    record = result.to_json()
    record["object_asset"] = record["object"]
    record.update(spec.summary_fields())
    return record


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
    """Run the trials of ``specs`` not yet in ``out_dir/trials.jsonl`` (the run engine:
    :func:`~simgrasp.runs.engine.run_resumable`), appending each as it finishes; return the
    records of all of ``specs`` (earlier and new), in ``specs`` order. Workers build each
    object's model before the first trial."""
    run = RunConfig(workers, backend, address, progress)
    check_defaults(Path(out_dir))
    check_meshes(Path(out_dir), list(dict.fromkeys(s.object for s in specs)))
    objects = tuple((name,) for name in dict.fromkeys(s.object for s in specs))
    work = Work(run_spec, (ycb_dir,), warm_up=prepare_object, warm_calls=objects)
    try:
        finished = run_resumable(
            specs,
            lambda spec: spec.key,
            trial_log(Path(out_dir) / TRIALS_FILE),
            lambda todo: run_tasks(work, todo, run),
            progress=progress,
            desc="evaluate",
            unit="trial",
            on_record=on_record,
        )
    finally:  # the trials run here (one local worker) used this process's session
        from simgrasp.grasping.session import close_worker_sessions

        close_worker_sessions()
    return [finished[spec.key] for spec in specs]


def check_plan(specs: Sequence[TrialSpec], ycb_dir: str | None) -> None:
    """Fail before any worker starts on an unknown gripper or object (or missing YCB data),
    naming the offending value."""
    from simgrasp.assets.registry import load_object
    from simgrasp.grippers import make_gripper

    for gripper in dict.fromkeys(spec.config.gripper for spec in specs):
        make_gripper(gripper)
    for name in dict.fromkeys(spec.object for spec in specs):
        load_object(name, ycb_dir)
