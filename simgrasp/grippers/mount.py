"""A gripper in a MuJoCo scene: floating on a free joint, welded to a mocap body.

:func:`attach_gripper` places a :class:`~simgrasp.grippers.base.Gripper` in a scene spec at
``world_T_tcp`` with a free joint welded to a mocap body, so the gripper follows commanded
poses while contacts can push back. After compiling, :meth:`GripperHandles.bind` resolves ids
into a :class:`BoundGripper` that issues commands and reads the state from ``mujoco.MjData``.

TCP convention (README): origin midway between the finger pads, +z the approach direction
(palm toward object), +y the direction in which the jaws open and close. Units: m, kg, N.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from functools import cache, cached_property

import numpy as np
from numpy.typing import NDArray

from simgrasp._mujoco import mujoco
from simgrasp.errors import SimgraspError
from simgrasp.grippers.base import Gripper
from simgrasp.transforms import make_transform, matrix_to_pos_quat

MOUNT_IMPRATIO = 10.0
"""MuJoCo's ``opt.impratio`` that :func:`attach_gripper` gives a scene (at least): a grip does
not creep under a steady load. Every trial's ratio before ``TrialConfig.impratio`` existed."""

WELD_SOLREF = (0.02, 1.0)
"""Weld (mocap -> gripper base) time constant and damping: soft enough that contacts push the
gripper back instead of teleporting it through the object, stiff enough to carry a 1 kg load
with millimeter lag."""


def attach_gripper(
    spec: mujoco.MjSpec,
    gripper: Gripper,
    world_T_tcp: NDArray[np.float64],
    prefix: str = "gripper/",
) -> GripperHandles:
    """Attach ``gripper`` to ``spec`` with its TCP at ``world_T_tcp`` (4x4, world frame).

    Adds a mocap body ``{prefix}mocap`` and a weld from it to the gripper's root body, and
    sets the parent's contact options (elliptic cones, ``impratio``, ``implicitfast``)
    because attaching drops the child's ``<option>``.
    """
    child = gripper.load_spec()
    root = _root_at_origin(child, gripper.root_body)
    for body in child.bodies:
        if body.name != "world":
            body.gravcomp = 1.0
    root.add_freejoint(name="free")
    spec.option.cone = mujoco.mjtCone.mjCONE_ELLIPTIC
    spec.option.impratio = max(spec.option.impratio, MOUNT_IMPRATIO)
    spec.option.integrator = mujoco.mjtIntegrator.mjINT_IMPLICITFAST

    world_T_root = np.asarray(world_T_tcp, float) @ np.linalg.inv(root_T_tcp(gripper))
    pos, quat = matrix_to_pos_quat(world_T_root)
    mocap = spec.worldbody.add_body(name=f"{prefix}mocap", pos=pos, quat=quat, mocap=True)
    frame = spec.worldbody.add_frame(pos=pos, quat=quat)
    spec.attach(child, prefix=prefix, frame=frame)
    weld = spec.add_equality(
        name=f"{prefix}weld",
        type=mujoco.mjtEq.mjEQ_WELD,
        objtype=mujoco.mjtObj.mjOBJ_BODY,
        name1=mocap.name,
        name2=f"{prefix}{gripper.root_body}",
    )
    data = np.zeros(len(weld.data))
    data[6] = 1.0  # relative pose: identity quaternion (anchor and offset zero)
    data[10] = 1.0  # torque scale
    weld.data = data
    weld.solref = WELD_SOLREF
    return GripperHandles(gripper, prefix)


@dataclass(frozen=True)
class GripperHandles:
    """Names of a gripper's elements in a scene spec (before compiling)."""

    gripper: Gripper
    prefix: str

    def bind(self, model: mujoco.MjModel) -> BoundGripper:
        """Resolve names into ids and addresses of a compiled ``model``."""
        p, g = self.prefix, self.gripper

        def body(name: str) -> int:
            return mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_BODY, p + name)

        root = body(g.root_body)
        mocap_body = body("mocap")
        free_joint = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_JOINT, p + "free")
        fingers = tuple(tuple(body(name) for name in side) for side in g.fingers)
        subtree = _subtree_bodies(model, root)
        gripper_geoms = np.flatnonzero(np.isin(model.geom_bodyid, subtree))
        finger_geoms = tuple(
            tuple(
                int(i)
                for i in np.flatnonzero(
                    np.isin(model.geom_bodyid, [b for f in side for b in _subtree_bodies(model, f)])
                )
            )
            for side in fingers
        )
        pads = tuple(
            tuple(mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_GEOM, p + n) for n in names)
            for names in g.pads
        )
        if (
            min(
                root,
                mocap_body,
                free_joint,
                *(f for side in fingers for f in side),
                *(i for ps in pads for i in ps),
            )
            < 0
        ):
            raise SimgraspError(f"gripper {g.name!r} with prefix {p!r} is not in this model")
        return BoundGripper(
            gripper=g,
            root_body=root,
            mocap_id=int(model.body_mocapid[mocap_body]),
            tcp_site=mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_SITE, p + g.tcp_site),
            free_qpos=int(model.jnt_qposadr[free_joint]),
            free_dof=int(model.jnt_dofadr[free_joint]),
            actuator=mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_ACTUATOR, p + g.actuator),
            geom_ids=tuple(int(i) for i in gripper_geoms),
            body_ids=tuple(int(b) for b in subtree),
            finger_geoms=finger_geoms,  # type: ignore[arg-type]
            pad_geoms=pads,  # type: ignore[arg-type]
            pad_depth=float(model.geom_size[pads[0][0], 1] + model.geom_size[pads[1][0], 1]),
            root_T_tcp=root_T_tcp(g),
            finger_solimp=model.geom_solimp[list(finger_geoms[0] + finger_geoms[1])].copy(),
        )


@dataclass(frozen=True)
class BoundGripper:
    """A gripper in a compiled model: commands and state readers (ids resolved once)."""

    gripper: Gripper
    root_body: int
    mocap_id: int
    tcp_site: int
    free_qpos: int
    free_dof: int
    actuator: int
    geom_ids: tuple[int, ...]
    """Every geom of the gripper (visual and collision)."""
    body_ids: tuple[int, ...]
    finger_geoms: tuple[tuple[int, ...], tuple[int, ...]]
    """(left, right) geoms of each finger's subtree (links and pads)."""
    pad_geoms: tuple[tuple[int, ...], tuple[int, ...]]
    pad_depth: float
    """Sum of the two pads' half thicknesses (m): pad center distance minus gap."""
    root_T_tcp: NDArray[np.float64] = field(repr=False)
    finger_solimp: NDArray[np.float64] = field(repr=False)
    """(n, 5) the compiled ``solimp`` of the ``finger_geoms`` (left then right), as the gripper
    model sets them: what a trial restores when its config keeps the model's own."""

    @cached_property
    def tcp_T_root(self) -> NDArray[np.float64]:
        """``root_T_tcp``'s inverse (4x4), computed once: :meth:`command_tcp` runs every
        control step."""
        return np.asarray(np.linalg.inv(self.root_T_tcp), dtype=np.float64)

    def set_opening(self, data: mujoco.MjData, opening: float) -> None:
        """Command the jaws to hold the pads ``opening`` meters apart (clipped to the range)."""
        width = float(np.clip(opening, 0.0, self.gripper.max_opening))
        data.ctrl[self.actuator] = self.gripper.ctrl_for_opening(width)

    def close(self, data: mujoco.MjData) -> None:
        """Command the jaws to squeeze with the full (force-limited) grip force."""
        data.ctrl[self.actuator] = self.gripper.ctrl_closed

    def opening(self, data: mujoco.MjData) -> float:
        """Current gap between the pads' inner faces along the TCP y axis (m)."""
        y_world = data.site_xmat[self.tcp_site].reshape(3, 3)[:, 1]
        left, right = self.pad_geoms[0][0], self.pad_geoms[1][0]
        return float((data.geom_xpos[right] - data.geom_xpos[left]) @ y_world) - self.pad_depth

    def world_T_tcp(self, data: mujoco.MjData) -> NDArray[np.float64]:
        """Current TCP pose (4x4, world frame)."""
        site = self.tcp_site
        return make_transform(data.site_xmat[site].reshape(3, 3), data.site_xpos[site])

    def command_tcp(self, data: mujoco.MjData, world_T_tcp: NDArray[np.float64]) -> None:
        """Move the mocap target so the TCP is pulled toward ``world_T_tcp`` (world frame)."""
        pos, quat = matrix_to_pos_quat(world_T_tcp @ self.tcp_T_root)
        data.mocap_pos[self.mocap_id] = pos
        data.mocap_quat[self.mocap_id] = quat

    def teleport(self, data: mujoco.MjData, world_T_tcp: NDArray[np.float64]) -> None:
        """Put the gripper (and its mocap target) at ``world_T_tcp`` at rest; call
        ``mj_forward`` afterwards. Finger joints keep their configuration."""
        self.command_tcp(data, world_T_tcp)
        data.qpos[self.free_qpos : self.free_qpos + 3] = data.mocap_pos[self.mocap_id]
        data.qpos[self.free_qpos + 3 : self.free_qpos + 7] = data.mocap_quat[self.mocap_id]
        data.qvel[self.free_dof : self.free_dof + 6] = 0.0


def _subtree_bodies(model: mujoco.MjModel, root: int) -> NDArray[np.int64]:
    """Ids of ``root`` and all its descendants."""
    ids = [root]
    for body in range(root + 1, model.nbody):
        if model.body_parentid[body] in ids:
            ids.append(body)
    return np.asarray(ids)


def _root_at_origin(spec: mujoco.MjSpec, root_body: str) -> mujoco.MjsBody:
    """Put ``root_body`` at its parent's origin, so its pose is the attachment frame's."""
    root = spec.body(root_body)
    root.pos = [0.0, 0.0, 0.0]
    root.quat = [1.0, 0.0, 0.0, 0.0]
    return root


@cache
def root_T_tcp(gripper: Gripper) -> NDArray[np.float64]:
    """Pose of the TCP site in the root body frame at the model's reference configuration."""
    spec = gripper.load_spec()
    _root_at_origin(spec, gripper.root_body)
    model = spec.compile()
    data = mujoco.MjData(model)
    mujoco.mj_forward(model, data)
    root = model.body(gripper.root_body).id
    site = model.site(gripper.tcp_site).id
    world_T_root = make_transform(data.xmat[root].reshape(3, 3), data.xpos[root])
    world_T_site = make_transform(data.site_xmat[site].reshape(3, 3), data.site_xpos[site])
    return np.linalg.inv(world_T_root) @ world_T_site
