"""``simgrasp trial OBJECT``: run one grasp trial on an object in MuJoCo and report the outcome.

Without ``--grasp`` the full chain runs: render the scene, detect handles, plan and execute
the best grasp. Every chain setting is a flag (``--detector.quadric.shell-test false``,
``--trial.hold-time 2``) or comes from ``--config FILE``; ``--print-config`` shows them.

The quadric detector's chain default adds a fine pass (``--detector.quadric.fine-half-size``
0.012, the preset ``two_scales``) to the plain defaults that ``detect`` and
``detect-eval`` use: the chain's clouds are fused rendered depth views, where a thin handle (a
lying mug's strap) is seen from two sides and the one-pass fits come out too wide. Give
``--detector.quadric.fine-half-size 0`` to detect as ``detect`` does.
"""

from __future__ import annotations

import json
import sys
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any, Literal

import numpy as np

from simgrasp.cli.object_options import MeshObjectOptions
from simgrasp.cli.options import YcbSource
from simgrasp.config import setting
from simgrasp.errors import SimgraspError
from simgrasp.grasping.trials.chain_config import ChainConfig
from simgrasp.grasping.trials.protocol import protocol_names

if TYPE_CHECKING:
    from simgrasp.grasping.session import Session

EXAMPLES = (
    "simgrasp trial gen_mug --seed 3 --placement upright --json",
    "simgrasp trial mug.obj --units mm --detector tenpas --render trial.mp4",
)
"""Command lines shown by ``--help``."""


@dataclass(frozen=True, kw_only=True)
class Options(YcbSource, MeshObjectOptions):
    object: str = setting(positional=True, metavar="OBJECT")
    """YCB id (025_mug or mug), generated tool (gen_hammer = gen_hammer_s0, or gen_hammer_s3
    for the sizes drawn from seed 3) or mesh file (read with --scale/--units/--mass/...)."""
    grasp: tuple[float, float, float, float, float, float, float] | None = setting(
        None, metavar=("X", "Y", "Z", "QW", "QX", "QY", "QZ")
    )
    """TCP pose to execute (m; TCP between the pads, +z approach, +y jaw direction); without
    it the full chain runs."""
    grasp_frame: Literal["world", "object"] = "world"
    """Frame of --grasp: world, or the object's mesh frame (placed at its scene pose)."""
    width: float | None = None
    """Jaw opening before closing for --grasp (m; default the gripper's maximum)."""
    protocol: str | None = setting(None, choices=protocol_names)
    """Trial protocol of --grasp, as label-grasps' (its phases and settings), instead of the
    --trial.* settings (default: those, whose defaults are the full protocol)."""
    seed: int = setting(0, main=True)
    """Seed of the scene (rest pose and yaw) and of the chain (noise, detection, planning), as
    in an evaluate record: the same object and seed rerun that trial."""
    json: bool = setting(False, main=True)
    """Print the trial record as JSON."""
    render: Path | None = setting(None, output="file", main=True)
    """Write key frames (pre-grasp, closed, lifted, perturbed): .png grid or .mp4."""
    record: bool = False
    """Add the states a replay needs to the record (``replay``: object and TCP poses, jaw
    opening at 30 Hz of sim time, phase names and times) for ``simgrasp view``."""
    chain: ChainConfig = setting(default_factory=ChainConfig, flatten=True)


def run(options: Options) -> int:
    from simgrasp.grasping.session import Session
    from simgrasp.scenes.key_frames import FrameRecorder, check_frames_target, write_frames

    _check_grasp_flags(options)
    if options.render is not None:
        check_frames_target(options.render)
    with Session(options.ycb_dir) as session:
        frames = FrameRecorder(session.renderers) if options.render is not None else None
        if options.record:
            record = _recorded_trial(options, frames, session)
        else:
            record = _trial(options, frames, session)
    if options.render is not None and frames is not None:
        record["render"] = write_frames(frames.frames, options.render)
    if options.json:
        print(json.dumps(record))
    else:
        _print_summary(record)
    return 0


def _check_grasp_flags(options: Options) -> None:
    """Refuse the flags of a given grasp without ``--grasp``, ``--protocol`` with ``--trial.*``
    settings, and a ``--grasp`` whose quaternion is not a unit one (within the tolerance of
    label-grasps, which marks such rows invalid)."""
    from simgrasp.grasping.labeling.grasp_sets import pose_problem

    if options.width is not None and options.grasp is None:
        raise SimgraspError("--width needs --grasp (the full chain plans its own jaw opening)")
    if options.protocol is not None and options.grasp is None:
        raise SimgraspError("--protocol needs --grasp (the full chain runs the --trial.* settings)")
    if options.grasp_frame != "world" and options.grasp is None:
        raise SimgraspError("--grasp-frame needs --grasp (the full chain plans its own grasp)")
    if options.protocol is not None and options.chain.trial != ChainConfig().trial:
        raise SimgraspError("give --protocol or --trial.* settings, not both")
    if options.grasp is not None and (problem := pose_problem(np.array(options.grasp))):
        raise SimgraspError(f"--grasp: {problem}: give a unit quaternion")


def _trial(options: Options, on_phase: Any, session: Session) -> dict[str, Any]:
    """The record of the given grasp's trial (``--grasp``) or of the full chain's."""
    if options.grasp:
        return _given_trial(options, on_phase, session)
    return _chain_trial(options, on_phase, session)


def _recorded_trial(options: Options, frames: Any, session: Session) -> dict[str, Any]:
    """:func:`_trial` with the states of a replay (:mod:`simgrasp.viewer.record`)."""
    from simgrasp.viewer.record import StateRecorder

    recorder = StateRecorder(next_phase=frames)
    with recorder.installed():
        record = _trial(options, recorder, session)
    record["replay"] = recorder.replay()
    return record


def _given_trial(options: Options, recorder: Any, session: Session) -> dict[str, Any]:
    """Execute the grasp given with ``--grasp``."""
    from simgrasp.grasping.trials.given_grasp import trial_of_grasp
    from simgrasp.grasping.trials.protocol import get_protocol
    from simgrasp.grippers import make_gripper

    assert options.grasp is not None
    trial_config, phases = options.chain.trial, None
    if options.protocol is not None:
        protocol = get_protocol(options.protocol)
        trial_config, phases = protocol.config, protocol.phases
    result = trial_of_grasp(
        session.model(options.object_name(options.object)),
        make_gripper(options.chain.gripper),
        options.grasp,
        frame=options.grasp_frame,
        width=options.width,
        scene_config=options.chain.scene,
        trial_config=trial_config,
        phases=phases,
        seed=options.seed,
        on_phase=recorder,
    )
    return result.to_json()


def _chain_trial(options: Options, recorder: Any, session: Session) -> dict[str, Any]:
    """Render, detect, plan and execute (see :mod:`simgrasp.grasping.trials.chain`); the
    record says which renderer made the depth (``render_backend``: GL and ray-cast depth
    differ at silhouettes, so a seed's trial depends on it, as ``evaluate`` records too)."""
    from simgrasp.grasping.trials.chain import run_chain
    from simgrasp.scenes.render import select_backend

    object_model = session.model(options.object_name(options.object))
    chain = run_chain(object_model, options.chain, options.seed, on_phase=recorder, session=session)
    record = chain.to_json()
    return {**record, "render_backend": select_backend()}


def _print_summary(record: dict[str, Any]) -> None:
    """A few lines for a person: the chain's detection (full chain only) and, when a grasp
    was executed, how it went."""
    outcome = {True: "success", False: f"failed ({record['failure']})", None: "sim unstable"}
    lines = [
        f"object       {record['object']}  (gripper {record['gripper']}, seed {record['seed']})",
        f"outcome      {outcome[record['success']]}",
    ]
    if "handles" in record:
        lines.append(
            f"detection    {record['handles']} handle(s) from {record['candidates']} "
            f"candidates on {record['cloud_points']} cloud points; "
            f"{record['grasp_candidates']} collision-free grasp(s)"
        )
    if record["failure"] != "no_grasp":
        source = record.get("handle_source", "shipped")
        handle_share = f"share of contacts {record['handle_fraction']:.2f}, {source} label"
        lines += [
            f"on handle    {record['on_handle']}  ({handle_share})",
            f"lift height  {record['lift_height']:.3f} m",
            f"sim time     {record['sim_time']:.2f} s in {record['timings_s']['total']:.2f} s wall",
        ]
    if "render" in record:
        lines.append(f"frames       {record['render'] or 'none: no grasp was executed'}")
    sys.stdout.write("\n".join(lines) + "\n")
