"""``simgrasp object show|export NAME``: look at an object model, or write it as a standalone MJCF.

``show`` renders two views side by side (MuJoCo offscreen renderer): the visual mesh, and the
colored collision hulls, both with the labeled handle region drawn in translucent red.
``export`` writes ``DIR/<name>.xml`` with a floor, the object resting on it in its most
probable stable pose, and its mesh/texture files beside it, so that
``python -m mujoco.viewer --mjcf DIR/<name>.xml`` opens it.
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from pathlib import Path
from typing import TYPE_CHECKING, Annotated, Literal

from simgrasp.cli.object_options import MeshObjectOptions
from simgrasp.cli.options import YcbSource
from simgrasp.config import setting
from simgrasp.config.checks import Range
from simgrasp.errors import SimgraspError

if TYPE_CHECKING:
    from simgrasp.assets.model import ObjectModel


EXAMPLES = (
    "simgrasp object show gen_hammer --out hammer.png",
    "simgrasp object export 033_spatula --out out/spatula",
)
"""Command lines shown by ``--help``."""


@dataclass(frozen=True, kw_only=True)
class Options(YcbSource, MeshObjectOptions):
    action: Literal["show", "export"] = setting(positional=True)
    """What to do with the object."""
    name: str = setting(positional=True, metavar="NAME")
    """YCB id or name (025_mug, mug), gen_<kind>[_s<seed>] or mesh file (read with
    --scale/--units/--mass/...)."""
    out: Path
    """show: PNG file to write; export: directory to write."""
    seed: int = 0
    """Sizes of generated objects named without _s<seed>."""
    size: Annotated[int, Range(ge=16)] = 480
    """show: height of each view (pixels)."""


def run(options: Options) -> int:
    from simgrasp.assets.model import build_object_model
    from simgrasp.assets.registry import load_object
    from simgrasp.runs.out_dir import check_out_dir, check_output_file

    if options.action == "show" and options.out.suffix.lower() != ".png":
        raise SimgraspError(f"--out for show must be a .png file, got {options.out}")
    if options.action == "show":  # --out is a file or a folder by the action: checked here
        check_output_file(options.out, "--out")
    else:
        check_out_dir(options.out)
    name = options.object_name(options.name)
    model = build_object_model(load_object(name, options.ycb_dir, seed=options.seed))
    if options.action == "show":
        from simgrasp.scenes.object_view import show_object

        show_object(model, options.out, options.size)
        print(
            f"{model.asset.name}: {len(model.hulls)} hulls, mass {model.asset.mass:.3f} kg "
            f"-> {options.out}"
        )
        return 0
    from simgrasp.assets.export import export_mjcf

    xml_path = export_mjcf(_file_named(model, name), options.out)
    print(f"{model.asset.name}: wrote {xml_path} (python -m mujoco.viewer --mjcf {xml_path})")
    return 0


def _file_named(model: ObjectModel, name: str) -> ObjectModel:
    """``model`` named, for the files of its export, by :func:`file_stem` (``DIR/mug.obj?units=mm``
    would write ``DIR/mug.obj?units=mm.xml`` outside --out)."""
    from simgrasp.assets.mesh_object import file_stem

    return replace(model, asset=replace(model.asset, name=file_stem(name)))
