"""Regenerate the example scenes in ``scenes/``: MJCF files that
``python -m mujoco.viewer --mjcf scenes/<name>.xml`` opens (table, object at its seed-0 rest
pose, the chain's four depth cameras, the parked gripper), and one cluttered scene: the
generated hammer among five generated distractors (``--clutter 5 --clutter-objects
generated``, seed 0, settled).

Committed: the scenes built only from our own assets (generated tools, the built-in gripper).
The Menagerie Robotiq and the YCB scans are third-party data we never ship, so no scene
holds them; a YCB object is exported with its files by ``simgrasp object export 048_hammer
--out DIR``.

    python scripts/export_example_scenes.py
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

from simgrasp.assets.model import model_for
from simgrasp.config.arguments import script_main
from simgrasp.config.checks import Checked
from simgrasp.grasping.trials.chain_config import ChainConfig
from simgrasp.grippers import make_gripper
from simgrasp.scenes.scene import build_scene

SCENES = Path(__file__).resolve().parents[1] / "scenes"
SHIPPED = (("gen_hammer", "builtin"), ("gen_mug", "builtin"))
"""(object, gripper) of the committed example scenes."""


CLUTTER = ChainConfig.of(scene__clutter=5, scene__clutter_objects="generated")
"""The committed cluttered scene's settings (only our own generated objects)."""


def export(
    object_name: str, gripper: str, out_dir: Path, config: ChainConfig, suffix: str = ""
) -> Path:
    """Write the seed-0 chain scene of ``object_name`` with ``gripper``; returns the XML."""
    scene = build_scene(model_for(object_name), make_gripper(gripper), config.scene, 0)
    return scene.export_xml(out_dir / f"{object_name}_{gripper}{suffix}.xml")


@dataclass(frozen=True, kw_only=True)
class Options(Checked):
    """No settings: the scenes and their settings are the module's constants."""


def run(options: Options) -> None:
    """Write the example scenes into ``scenes/``, printing each file."""
    for object_name, gripper in SHIPPED:
        print(export(object_name, gripper, SCENES, ChainConfig()))
    print(export("gen_hammer", "builtin", SCENES, CLUTTER, "_clutter5"))


def main() -> int:
    return script_main(Options, run, __doc__.splitlines()[0])


if __name__ == "__main__":
    raise SystemExit(main())
