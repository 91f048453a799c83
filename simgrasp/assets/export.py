"""An object model as a standalone MJCF: a floor and the object resting on it in its most
probable stable pose, mesh and texture files beside the XML, so that
``python -m mujoco.viewer --mjcf DIR/<name>.xml`` opens it."""

from __future__ import annotations

from pathlib import Path
from xml.etree import ElementTree

from simgrasp._mujoco import mujoco
from simgrasp.assets.model import ObjectModel
from simgrasp.assets.stable import stable_poses

DROP_HEIGHT = 0.003
"""Meters above the floor the exported object starts."""


def export_mjcf(model: ObjectModel, out_dir: Path) -> Path:
    """Write ``out_dir/<name>.xml`` plus mesh/texture files; return the XML path."""
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
