"""``simgrasp object show|export NAME``: look at an object model, or write it as a standalone MJCF.

``show`` renders two views side by side (MuJoCo offscreen renderer; ``MUJOCO_GL=egl`` unless
set): the visual mesh, and the colored collision hulls, both with the labeled handle region
drawn in translucent red. ``export`` writes ``DIR/<name>.xml`` with a floor, the object resting
on it in its most probable stable pose, and its mesh/texture files beside it, so that
``python -m mujoco.viewer --mjcf DIR/<name>.xml`` opens it.
"""

from __future__ import annotations

import argparse
import os
from pathlib import Path
from xml.etree import ElementTree

import numpy as np

LABEL_GROUP = 4
LABEL_RGBA = (1.0, 0.1, 0.1, 0.35)
DROP_HEIGHT = 0.003  # meters above the floor the exported object starts


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("action", choices=("show", "export"), help="what to do with the object")
    parser.add_argument("name", help="YCB id or name (025_mug, mug) or gen_<kind>[_s<seed>]")
    parser.add_argument(
        "--out", required=True, help="show: PNG file to write; export: directory to write"
    )
    parser.add_argument("--ycb-dir", default=None, help="YCB download (default $SIMGRASP_YCB_DIR)")
    parser.add_argument("--seed", type=int, default=0, help="sizes of generated objects")
    parser.add_argument("--size", type=int, default=480, help="show: height of each view (px)")


def _add_label_geoms(spec, body, model, name: str) -> None:  # noqa: ANN001 - mujoco types
    from simgrasp._mujoco import mujoco
    from simgrasp.assets.labels import Capsule
    from simgrasp.transforms import rotation_to_quat_wxyz

    for i, region in enumerate(model.asset.handle.regions):
        common = dict(
            name=f"{name}_label{i}", group=LABEL_GROUP, contype=0, conaffinity=0, rgba=LABEL_RGBA
        )
        if isinstance(region, Capsule):
            body.add_geom(
                type=mujoco.mjtGeom.mjGEOM_CAPSULE,
                fromto=np.concatenate([region.p0, region.p1]),
                size=[region.radius, 0, 0],
                **common,
            )
        else:
            body.add_geom(
                type=mujoco.mjtGeom.mjGEOM_BOX,
                pos=region.center,
                quat=rotation_to_quat_wxyz(region.object_R_box),
                size=region.half_extents,
                **common,
            )


def _show(model, out: Path, size: int) -> None:  # noqa: ANN001
    from PIL import Image

    from simgrasp._mujoco import mujoco

    spec = mujoco.MjSpec()
    spec.visual.headlight.ambient = [0.4, 0.4, 0.4]
    spec.visual.global_.offwidth = 2 * size
    spec.visual.global_.offheight = size
    body = model.add_to(spec, np.eye(4), name="object")
    _add_label_geoms(spec, body, model, "object")
    if model.asset.handle.whole_object:
        spec.geom("object_visual").rgba = [1.0, 0.45, 0.45, 1.0]
    compiled = spec.compile()
    data = mujoco.MjData(compiled)
    mujoco.mj_forward(compiled, data)
    camera = mujoco.MjvCamera()
    bounds = model.asset.mesh.bounds
    camera.lookat[:] = bounds.mean(axis=0)
    camera.distance = 2.2 * float(np.linalg.norm(bounds[1] - bounds[0]))
    camera.azimuth, camera.elevation = 135.0, -35.0
    panels = []
    with mujoco.Renderer(compiled, height=size, width=size) as renderer:
        for groups in ((2, LABEL_GROUP), (3, LABEL_GROUP)):
            option = mujoco.MjvOption()
            option.geomgroup[:] = 0
            for group in groups:
                option.geomgroup[group] = 1
            renderer.update_scene(data, camera=camera, scene_option=option)
            panels.append(renderer.render())
    out.parent.mkdir(parents=True, exist_ok=True)
    Image.fromarray(np.concatenate(panels, axis=1)).save(out)


def export_mjcf(model, out_dir: Path) -> Path:  # noqa: ANN001
    """Write ``out_dir/<name>.xml`` plus mesh/texture files; return the XML path."""
    from simgrasp._mujoco import mujoco
    from simgrasp.assets.stable import stable_poses

    out_dir.mkdir(parents=True, exist_ok=True)
    name = model.asset.name
    spec = mujoco.MjSpec()
    spec.modelname = name
    spec.meshdir = f"{out_dir.resolve()}/"
    spec.texturedir = f"{out_dir.resolve()}/"
    spec.worldbody.add_geom(
        name="floor", type=mujoco.mjtGeom.mjGEOM_PLANE, size=[1.0, 1.0, 0.05], rgba=[0.6] * 3 + [1]
    )
    spec.worldbody.add_light(name="light", pos=[0, 0, 1.5], dir=[0, 0, -1])
    world_T_object = stable_poses(model)[0].rest_T_object.copy()
    world_T_object[2, 3] += DROP_HEIGHT
    model.add_to(spec, world_T_object, name=name, files_dir=out_dir)
    spec.compile()
    # Files sit beside the XML: drop the absolute directories used to compile here.
    root = ElementTree.fromstring(spec.to_xml())
    for compiler in root.iter("compiler"):
        compiler.attrib.pop("meshdir", None)
        compiler.attrib.pop("texturedir", None)
    xml_path = out_dir / f"{name}.xml"
    ElementTree.ElementTree(root).write(xml_path, encoding="unicode")
    return xml_path


def run(args: argparse.Namespace) -> int:
    os.environ.setdefault("MUJOCO_GL", "egl")
    from simgrasp.assets.model import build_object_model
    from simgrasp.assets.registry import load_object

    if args.size < 16:
        raise ValueError(f"--size must be at least 16 pixels, got {args.size}")
    model = build_object_model(load_object(args.name, args.ycb_dir, seed=args.seed))
    out = Path(args.out)
    if args.action == "show":
        if out.suffix.lower() != ".png":
            raise ValueError(f"--out for show must be a .png file, got {out}")
        _show(model, out, args.size)
        print(
            f"{model.asset.name}: {len(model.hulls)} hulls, mass {model.asset.mass:.3f} kg -> {out}"
        )
    else:
        xml_path = export_mjcf(model, out)
        print(f"{model.asset.name}: wrote {xml_path} (python -m mujoco.viewer --mjcf {xml_path})")
    return 0
