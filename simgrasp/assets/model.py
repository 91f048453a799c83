"""MuJoCo models of objects: a visual mesh, convex collision hulls and explicit inertia.

An ``ObjectModel`` is built once per object (CoACD decomposition, cached on disk) and can be
added to any number of ``mujoco.MjSpec`` scenes. Everything is in the object's own frame
(meters, kilograms) until ``add_to`` places the body at ``world_T_object``.
"""

from __future__ import annotations

import functools
import shutil
from dataclasses import dataclass, replace
from pathlib import Path

import numpy as np
import trimesh
from numpy.typing import NDArray
from PIL import Image

from simgrasp._mujoco import mujoco
from simgrasp.assets.decompose import DecompositionConfig, decompose
from simgrasp.assets.object import ObjectAsset
from simgrasp.assets.registry import load_object
from simgrasp.errors import SimgraspError
from simgrasp.transforms import rotation_to_quat_wxyz

VISUAL_GROUP = 2
COLLISION_GROUP = 3
HULL_COLORS = np.array(
    [
        [0.90, 0.30, 0.25, 1.0],
        [0.25, 0.60, 0.90, 1.0],
        [0.35, 0.80, 0.35, 1.0],
        [0.95, 0.75, 0.20, 1.0],
        [0.65, 0.40, 0.85, 1.0],
        [0.20, 0.80, 0.80, 1.0],
    ]
)
GENERATED_RGBA = (0.72, 0.62, 0.50, 1.0)
MAX_TEXTURE_SIDE = 1024
"""Object textures are downscaled to at most this many pixels a side. A YCB scan's 4096 x 4096
map (48 MB of RGB) cost ~0.13 s to upload to a software GL context in every scene, and an
object covers a few hundred pixels of a 640 x 480 picture."""


@dataclass(frozen=True)
class Inertial:
    """Mass properties in the object frame: ``com_object`` (m) and ``inertia_com`` (kg m^2,
    3 x 3, about the center of mass, axes of the object frame)."""

    mass: float
    com_object: NDArray[np.float64]
    inertia_com: NDArray[np.float64]


@dataclass(frozen=True)
class ObjectModel:
    """An object ready for MuJoCo: asset (mesh, handle label, mass), hulls and contact params.

    ``hulls`` are convex meshes in the object frame. ``friction`` is MuJoCo's (sliding,
    torsional, rolling); ``condim`` 6 adds torsional and rolling friction to the sliding
    cone, so round objects (cans, fruit) stop rolling as real ones do.
    """

    asset: ObjectAsset
    hulls: tuple[trimesh.Trimesh, ...]
    inertial: Inertial
    friction: tuple[float, float, float] = (0.8, 0.01, 0.001)
    condim: int = 6
    solref: tuple[float, float] = (0.01, 1.0)
    solimp: tuple[float, float, float, float, float] = (0.95, 0.99, 0.001, 0.5, 2.0)

    def add_to(
        self,
        spec: mujoco.MjSpec,
        world_T_object: NDArray[np.float64],
        name: str = "object",
        files_dir: Path | None = None,
    ) -> mujoco.MjsBody:
        """Add the object as a free body ``name`` under ``spec.worldbody``.

        ``world_T_object`` (4 x 4) places the object frame. Geoms: ``<name>_visual`` (group 2,
        no contacts, textured when the asset has a texture) and one ``<name>_hull<i>`` per
        convex hull (group 3). Assets are prefixed with ``name`` so objects can coexist.
        With ``files_dir``, mesh and texture files are written there and referenced by file
        name (for a standalone MJCF; set ``spec.meshdir``/``texturedir`` to that directory);
        otherwise the data is passed in memory.
        """
        world_T_object = np.asarray(world_T_object, dtype=float)
        if world_T_object.shape != (4, 4) or not np.all(np.isfinite(world_T_object)):
            raise SimgraspError(f"world_T_object for {name!r} must be a finite 4x4 matrix")
        body = spec.worldbody.add_body(
            name=name,
            pos=world_T_object[:3, 3],
            quat=rotation_to_quat_wxyz(world_T_object[:3, :3]),
        )
        body.add_freejoint(name=f"{name}_free")
        body.explicitinertial = True
        body.mass = self.asset.mass
        body.ipos = self.inertial.com_object
        inertia = self.inertial.inertia_com
        body.fullinertia = [
            inertia[0, 0],
            inertia[1, 1],
            inertia[2, 2],
            inertia[0, 1],
            inertia[0, 2],
            inertia[1, 2],
        ]
        self._add_visual(spec, body, name, files_dir)
        for i, hull in enumerate(self.hulls):
            mesh_name = f"{name}_hull{i}"
            mesh = spec.add_mesh(name=mesh_name)
            if files_dir is None:
                mesh.uservert, mesh.userface = self._hull_lists[i]
            else:
                hull.export(files_dir / f"{mesh_name}.stl")
                mesh.file = f"{mesh_name}.stl"
            body.add_geom(
                name=mesh_name,
                type=mujoco.mjtGeom.mjGEOM_MESH,
                meshname=mesh_name,
                group=COLLISION_GROUP,
                condim=self.condim,
                friction=list(self.friction),
                solref=list(self.solref),
                solimp=list(self.solimp),
                rgba=HULL_COLORS[i % len(HULL_COLORS)],
            )
        return body

    @functools.cached_property
    def _hull_lists(self) -> tuple[tuple[list[float], list[int]], ...]:
        """Each hull's flat vertices (m) and faces as :meth:`add_to` hands them to MjSpec,
        built once: MjSpec copies a list about ten times faster than an array (which it reads
        element by element), the same values."""
        return tuple(_flat_lists(hull) for hull in self.hulls)

    @functools.cached_property
    def _visual_lists(self) -> tuple[list[float], list[int]]:
        """The visual mesh's flat vertices (m) and faces, as :attr:`_hull_lists`."""
        return _flat_lists(self.asset.mesh)

    def _add_visual(
        self, spec: mujoco.MjSpec, body: mujoco.MjsBody, name: str, files_dir: Path | None
    ) -> None:
        asset = self.asset
        mesh_name = f"{name}_visual"
        mesh = spec.add_mesh(name=mesh_name, inertia=mujoco.mjtMeshInertia.mjMESH_INERTIA_SHELL)
        geom = body.add_geom(
            name=mesh_name,
            type=mujoco.mjtGeom.mjGEOM_MESH,
            meshname=mesh_name,
            group=VISUAL_GROUP,
            contype=0,
            conaffinity=0,
            mass=0.0,
            rgba=GENERATED_RGBA,
        )
        if asset.texture_file is not None and asset.mesh_file is not None:
            # MuJoCo reads the OBJ's UVs itself; it cannot decode JPEG, so the texture goes
            # in as RGB pixels (or a PNG next to the exported MJCF).
            suffix = Path(asset.mesh_file).suffix.lower()
            if files_dir is None:
                mesh.file = str(asset.mesh_file)
            else:
                shutil.copyfile(asset.mesh_file, files_dir / f"{mesh_name}{suffix}")
                mesh.file = f"{mesh_name}{suffix}"
            if suffix == ".obj":
                _add_texture(spec, name, Path(asset.texture_file), files_dir)
                geom.material = f"{name}_material"
                geom.rgba = [1.0, 1.0, 1.0, 1.0]
            return
        if files_dir is None:
            mesh.uservert, mesh.userface = self._visual_lists
        else:
            asset.mesh.export(files_dir / f"{mesh_name}.stl")
            mesh.file = f"{mesh_name}.stl"


def _flat_lists(mesh: trimesh.Trimesh) -> tuple[list[float], list[int]]:
    """A mesh's vertices (m) and faces as flat Python lists, row after row."""
    return mesh.vertices.ravel().tolist(), mesh.faces.ravel().tolist()


def _add_texture(
    spec: mujoco.MjSpec, name: str, texture_file: Path, files_dir: Path | None
) -> None:
    try:
        stat = texture_file.stat()
        width, height, rgb = _texture_rgb(str(texture_file), stat.st_mtime_ns, stat.st_size)
    except OSError as exc:
        raise SimgraspError(f"object {name!r}: cannot read texture {texture_file}: {exc}") from exc
    texture_name = f"{name}_texture"
    if files_dir is None:
        texture = spec.add_texture(
            name=texture_name,
            type=mujoco.mjtTexture.mjTEXTURE_2D,
            width=width,
            height=height,
            nchannel=3,
        )
        texture.data = rgb
    else:
        Image.frombytes("RGB", (width, height), rgb).save(files_dir / f"{texture_name}.png")
        spec.add_texture(
            name=texture_name, type=mujoco.mjtTexture.mjTEXTURE_2D, file=f"{texture_name}.png"
        )
    material = spec.add_material(name=f"{name}_material")
    material.textures[mujoco.mjtTextureRole.mjTEXROLE_RGB] = texture_name


@functools.lru_cache(maxsize=8)
def _texture_rgb(path: str, mtime_ns: int, size: int) -> tuple[int, int, bytes]:
    """(width, height, RGB bytes) of an image file, at most ``MAX_TEXTURE_SIDE`` pixels a
    side, decoded once per process and file version (a YCB texture takes ~0.25 s to decode;
    every scene of a sweep needs it)."""
    with Image.open(path) as image:
        rgb = image.convert("RGB")
    rgb.thumbnail((MAX_TEXTURE_SIDE, MAX_TEXTURE_SIDE), Image.Resampling.LANCZOS)
    return rgb.width, rgb.height, rgb.tobytes()


def inertial_properties(asset: ObjectAsset, hulls: tuple[trimesh.Trimesh, ...]) -> Inertial:
    """Uniform-density mass properties scaled to ``asset.mass``.

    From the mesh when it is watertight, else from the union of the convex hulls (their
    overlaps counted twice, a small error for CoACD hulls). Principal moments are raised to
    at least mass x ``MIN_RADIUS_OF_GYRATION``² (see there).
    """
    solid_mesh = asset.mesh.is_watertight and asset.mesh.volume > 0
    solids = [asset.mesh] if solid_mesh else list(hulls)
    volumes = np.array([s.volume for s in solids])
    if not np.all(volumes > 0):
        raise SimgraspError(f"object {asset.name!r}: a solid used for its inertia has no volume")
    density = asset.mass / volumes.sum()
    com = sum(v * s.center_mass for v, s in zip(volumes, solids, strict=True)) / volumes.sum()
    inertia = np.zeros((3, 3))
    for volume, solid in zip(volumes, solids, strict=True):
        offset = solid.center_mass - com
        # moment_inertia is about the solid's own center of mass for unit density
        inertia += density * solid.moment_inertia + density * volume * (
            offset @ offset * np.eye(3) - np.outer(offset, offset)
        )
    return Inertial(float(asset.mass), np.asarray(com, dtype=float), _floored(inertia, asset.mass))


MIN_RADIUS_OF_GYRATION = 0.01
"""m. A thin tool's moment about its long axis is tiny (a fork: mass x (6 mm)², 1e-6 kg m²);
when such a tool squirts out of the pads, MuJoCo's 2 ms steps turn the pads' stored contact
energy (~0.03 J) into tumbling at over 100 rad/s (~0.7 J), a divergence. With no moment below
mass x (1 cm)² the release stays physical. Of the YCB set only the fork, spoon and knife are
raised; in the paper-object sweep none of the fork's 90 trials diverges any more (18 did)."""


def _floored(inertia: NDArray[np.float64], mass: float) -> NDArray[np.float64]:
    """``inertia`` (3 x 3, kg m²) with its principal moments raised to at least
    ``mass`` x ``MIN_RADIUS_OF_GYRATION``² about the same principal axes."""
    moments, axes = np.linalg.eigh(inertia)
    floor = mass * MIN_RADIUS_OF_GYRATION**2
    if moments.min() >= floor:
        return inertia
    return axes @ np.diag(np.maximum(moments, floor)) @ axes.T


def default_decomposition(asset: ObjectAsset) -> DecompositionConfig:
    """The CoACD settings for ``asset``: generated objects are unions of closed parts, so
    they skip CoACD's voxel remeshing (which would thicken thin parts by ~7 mm)."""
    if asset.source == "generated":
        return DecompositionConfig(preprocess_mode="off")
    return DecompositionConfig()


def build_object_model(
    asset: ObjectAsset, config: DecompositionConfig | None = None
) -> ObjectModel:
    """Decompose ``asset`` (cached) and compute its inertia; ``config`` defaults per source."""
    if not asset.mass > 0:
        raise SimgraspError(f"object {asset.name!r}: mass must be positive, got {asset.mass}")
    hulls = decompose(asset.mesh, config or default_decomposition(asset), asset.name)
    model = ObjectModel(asset=asset, hulls=hulls, inertial=inertial_properties(asset, hulls))
    if asset.friction is not None:
        model = replace(model, friction=(asset.friction, *model.friction[1:]))
    return model


def model_for(object_name: str, ycb_dir: str | None = None) -> ObjectModel:
    """The simulation model of an object by name (CoACD decomposition from the on-disk cache)."""
    return build_object_model(load_object(object_name, ycb_dir))
