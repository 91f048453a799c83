"""The ``simgrasp`` command line: one sub-command per user task.

Each sub-command lives beside the stage it drives, in a module with two functions:
``add_arguments(parser)`` and ``run(args) -> int``. Only the chosen command's module is
imported, so ``simgrasp detect`` does not pay for MuJoCo and vice versa.
"""

from __future__ import annotations

import argparse
import importlib
import sys
from collections.abc import Sequence

# name -> (module, one-line help)
COMMANDS: dict[str, tuple[str, str]] = {
    "demo": ("simgrasp.evaluation.demo_cli", "run the main job on the embedded default"),
    "detect": ("simgrasp.handles.detect_cli", "detect handles in a point cloud file"),
    "detect-eval": (
        "simgrasp.handles.eval_cli",
        "detection accuracy on YCB meshes (paper Tables I and II)",
    ),
    "labels": ("simgrasp.handles.labels_cli", "render objects with their labeled handles"),
    "fetch-ycb": ("simgrasp.assets.fetch_cli", "download YCB objects from the official site"),
    "object": ("simgrasp.assets.object_cli", "show or export an object model"),
    "trial": ("simgrasp.grasping.trial_cli", "run one grasp trial in MuJoCo"),
    "evaluate": ("simgrasp.evaluation.evaluate_cli", "sweep objects x detectors x grippers"),
    "sample-grasps": ("simgrasp.grasping.sample_cli", "antipodal grasps on an object's mesh"),
    "label-grasps": ("simgrasp.grasping.label_cli", "score every grasp of a grasp file"),
    "compare-labels": ("simgrasp.grasping.compare_cli", "agreement of two label-grasps runs"),
}


def _parser(command: str | None) -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(prog="simgrasp", description=__doc__.splitlines()[0])
    sub = parser.add_subparsers(dest="command", metavar="COMMAND", required=True)
    for name, (module_name, help_text) in COMMANDS.items():
        cmd = sub.add_parser(name, help=help_text, description=help_text)
        if name == command:
            importlib.import_module(module_name).add_arguments(cmd)
    return parser


def main(argv: Sequence[str] | None = None) -> int:
    argv = list(sys.argv[1:] if argv is None else argv)
    command = next((a for a in argv if not a.startswith("-")), None)
    command = command if command in COMMANDS else None
    args = _parser(command).parse_args(argv)
    module = importlib.import_module(COMMANDS[args.command][0])
    try:
        return int(module.run(args) or 0)
    except (ValueError, FileNotFoundError) as exc:
        print(f"simgrasp {args.command}: error: {exc}", file=sys.stderr)
        return 2


if __name__ == "__main__":
    sys.exit(main())
