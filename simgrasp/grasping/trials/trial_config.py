"""Every parameter of a grasp trial (SI units: m, s, m/s, N) and the settings of the
registered protocols (:mod:`simgrasp.grasping.trials.protocol`); free of MuJoCo imports."""

from __future__ import annotations

from dataclasses import dataclass, replace
from typing import Annotated, Literal

import numpy as np

from simgrasp.config.checks import Checked, Fraction, NonNegative, Positive, PositiveInt, Range
from simgrasp.grasping.trials.shake import ShakeConfig

ON_HANDLE_THRESHOLD = 0.5
"""A grasp is ``on_handle`` when at least this share of its finger-object contact points (at
the end of the hold) lies inside the labeled handle region."""


HANDLE_MARGIN = 0.005
"""Contact points within this distance (m) of a handle region count as on it: contacts lie on
the convex collision hulls, which bulge a few millimeters beyond the surface the labels were
drawn around."""

_DIRECTIONS = ((1, 0, 0), (-1, 0, 0), (0, 1, 0), (0, -1, 0), (0, 0, 1), (0, 0, -1))


@dataclass(frozen=True)
class TrialConfig(Checked):
    """Every parameter of a grasp trial (SI units: m, s, m/s, N)."""

    timestep: Positive = 0.002
    """Physics time step (s)."""
    control_steps: PositiveInt = 10
    """Physics steps between control updates (``mj_step`` with ``nstep``)."""
    hold_timestep: Positive | None = None
    """Physics time step (s) from the hold on (the hold, the tugs and their rests), at most the
    gripper's ``max_timestep``, in whole steps per control period of about the same length;
    None: ``timestep`` throughout. The jaws' impact in the close and the lift's start need the
    fine step; a grip under slowly changing loads may not."""
    impratio: Positive = 10.0
    """The contact solver's ratio of frictional to normal constraint impedance (MuJoCo's
    ``opt.impratio``) during the trial. By default the value every mounted gripper's scene
    gets (:data:`simgrasp.grippers.mount.MOUNT_IMPRATIO`): a grip does not creep under a
    steady load. The ``acronym`` protocol's lower ratio lets a grip slide as FleX's does
    (docs/results/acronym)."""
    integrator: Literal["implicitfast", "discrete"] = "implicitfast"
    """MuJoCo's integrator during the trial. ``implicitfast`` (every mounted gripper's scene)
    solves the contacts before it applies the fingers' joint damping, so a finger pressing
    with its full force on a light object can throw it: a 15 g mug flew 1.4 m in the close.
    ``discrete`` solves contacts and damping together: the object moves with the damped finger
    (``acronym``'s objects weigh 1-40 g; docs/results/acronym)."""
    finger_solimp_width: Positive | None = None
    """Penetration (m) over which the fingers' contacts stiffen from their softest to their
    stiffest (MuJoCo's ``solimp[2]`` of the finger geoms) during the trial; None: the gripper
    model's own (1 mm for the built-in and Franka fingers). ``acronym``'s 7 mm, chosen with
    its ``impratio`` on the tune half, raised FleX agreement (docs/results/acronym)."""
    settle_time: NonNegative = 0.5
    """Time the object rests on the table before the grasp (s)."""
    pregrasp_distance: Positive = 0.10
    """How far back along the approach the open gripper starts (m)."""
    approach_speed: Positive = 0.10
    """Speed of the approach from the pre-grasp to the grasp pose (m/s)."""
    close_time: Positive = 0.8
    """Time the jaws close and squeeze before the lift (s)."""
    squeeze_time: Positive | None = None
    """With it, the close ends this long (s) after both fingers first touch the object (at the
    latest after ``close_time``), however far the jaws had to travel; None: the close lasts
    ``close_time``."""
    lift_height: Positive = 0.20
    """How high the gripper lifts (m)."""
    lift_speed: Positive = 0.20
    """Lift speed (m/s)."""
    hold_time: NonNegative = 1.0
    """Time the lifted object is held still before the tugs (s)."""
    perturb_directions: tuple[tuple[float, float, float], ...] = _DIRECTIONS
    """World-frame directions of the tugs (normalized)."""
    perturb_force_scale: NonNegative = 1.0
    """Tug force as a multiple of the object's weight."""
    perturb_time: Positive = 0.3
    """Duration of each tug (s)."""
    perturb_rest: NonNegative | None = None
    """Rest after each tug (s); None: as long as the tug (``perturb_time``)."""
    on_handle_threshold: Fraction = ON_HANDLE_THRESHOLD
    """Share of finger contacts inside the handle label that makes a grasp ``on_handle``."""
    handle_margin: NonNegative = HANDLE_MARGIN
    """Contacts this close (m) to the handle label count as on it (see scoring)."""
    lifted_fraction: Annotated[float, Range(gt=0, le=1)] = 0.5
    """The object counts as lifted when it rose at least this share of ``lift_height``."""
    approach_lag_limit: Positive = 0.02
    """TCP more than this far from its target after the approach: ``approach_collision``."""
    approach_push_limit: Positive = 0.03
    """Object moved more than this during the approach: ``approach_collision``."""
    release_gap: Positive = 0.01
    """After the close, an object at least this far (m) from every gripper geom has been let
    go, and the trial ends with the phase's failure (``slipped_in_lift``,
    ``dropped_in_perturbation``). A gap, not a lost contact, decides it: a tool rattling in
    the jaws under a tug has no contact at some control steps."""
    max_penetration: Positive = 0.02
    """Any contact deeper than this (m) counts as divergence."""
    free_floating: bool = False
    """ACRONYM-style trial in free space: the object starts ``float_height`` above its rest
    pose with its gravity compensated, the gripper appears at the grasp pose itself (no
    pre-grasp, no approach; touching the object there is ``invalid_start``) and closes; then
    the object's gravity is switched on and, with the gripper still (no lift), it must stay in
    the jaws through the hold and the tugs. ``lift_height`` then only sets how far the object
    may sag (``lifted_fraction`` of it) before it counts as dropped."""
    float_height: NonNegative = 0.5
    """How far (m) above its rest pose a free-floating object starts (the table stays below,
    out of reach)."""
    quiet_speed: Positive | None = None
    """Early end of the waiting phases: the settle, the close, the hold, each tug after
    ``quiet_min_tug`` and each rest end once no point of the object has moved faster than
    this relative to the gripper, and no finger joint either (m/s; rad/s for a hinge), for
    ``quiet_time``: the grip is at rest, and more waiting changes nothing. None: every phase
    runs its full time (the full protocol)."""
    quiet_time: NonNegative = 0.06
    """How long (s) the scene must stay below ``quiet_speed`` to end a waiting phase."""
    quiet_min_tug: NonNegative = 0.1
    """A tug lasts at least this long (s) before it may end at rest: the force first has to
    move whatever it can move."""
    sleep: bool = False
    """Let MuJoCo put resting bodies to sleep (``mjENBL_SLEEP``, ``opt.sleep_tolerance``):
    the object lying still on the table during the settle and the approach is not simulated
    until the gripper touches it, which wakes it with the same contacts. Only the cost of those
    phases changes (an object at rest stays where it is)."""
    start_tolerance: Positive | None = None
    """Free-floating starts: gripper contacts at the grasp pose up to this deep (m) are no
    ``invalid_start`` (the object's convex hulls bulge a few millimeters beyond the mesh a
    grasp file was checked against); None: any contact is."""
    shake: ShakeConfig | None = None
    """With it, the closed grasp is tested by ACRONYM's shake
    (:mod:`simgrasp.grasping.trials.shake`) instead of the lift, the hold and the tugs; None:
    not used."""
    max_speed: Positive = 100.0
    """Any generalized velocity above this (m/s or rad/s) counts as divergence (a light tool
    spinning in the jaws during the tugs reaches ~20 rad/s; blow-ups go far beyond)."""

    def _check(self) -> None:
        directions = np.asarray(self.perturb_directions, dtype=float).reshape(-1, 3)
        if np.any(np.linalg.norm(directions, axis=1) < 1e-9):
            self.refuse("perturb_directions", "holds a zero vector (directions must be non-zero)")

    @property
    def control_dt(self) -> float:
        return self.timestep * self.control_steps

    @property
    def rest_time(self) -> float:
        """Rest after each tug (s)."""
        return self.perturb_time if self.perturb_rest is None else self.perturb_rest


FAST_TRIAL = TrialConfig(
    settle_time=0.1,
    approach_speed=0.2,
    squeeze_time=0.15,
    lift_speed=0.5,
    hold_time=0.25,
    hold_timestep=0.004,
    quiet_speed=0.01,
    quiet_time=0.04,
    quiet_min_tug=0.04,
    sleep=True,
)
"""The ``fast`` protocol for labeling grasp sets: the full one with what does not change verdicts
cut away.

- Shorter phases: 0.1 s settle, the 10 cm approach at 0.2 m/s, a close that squeezes 0.15 s
  once both fingers touch (the full close's 0.8 s at most: a fully open gripper needs 0.43 s
  to close its stroke), 0.25 s hold; the same 20 cm lift at 0.5 m/s and six 0.3 s tugs with
  0.3 s rests.
- Waiting ends at rest: the settle, the close, the hold, each tug after 0.04 s and each rest end
  once the object has been still in the jaws for 40 ms (every point under 1 cm/s relative to
  the gripper, the fingers too): a grip at rest under a constant load stays as it is.
- A 4 ms time step from the hold on (5 steps per 20 ms control period), 2 ms before it, for
  grippers measured to allow it (``Gripper.max_timestep``: the built-in one; the Robotiq
  2F-85 keeps 2 ms: at 3 ms its verdicts on 100 hammer grasps agreed on 90 %, at 2 ms 96 %).
- The object sleeps while it lies still on the table (``sleep``): the approach's steps cost
  about two thirds as much.

What had to stay, measured on sampled grasps against the full protocol:

- the 20 cm lift: a tool held off its center of mass sags by centimeters in the jaws, which a
  10 cm lift's 5 cm threshold counted as a drop (84 % agreement on the YCB hammer);
- 0.3 s tugs: 0.2 s ones kept nine hammer grasps the full protocol drops (94.5 %);
- a 0.2 m/s approach: at 0.4 m/s the mug agreed on 92 %;
- 0.3 s rests between the tugs: with 0.1 s rests the Robotiq's verdicts on the hammer agreed on
  85 % (the tool still swings when the next tug comes);
- the 2 ms step through the close and the lift: 3 ms throughout gave 93 %, 3 ms from both
  fingers' touch on 89 % on the hammer (5 ms from the hold on: only 5 % faster than 4 ms);
- a 0.15 s squeeze: after 0.1 s the hammer agreed on 95.8 % over its 2000 grasps (96.8 %
  after 0.15 s, 98.0 % after the 0.25 s of the protocol before);
- a 1 cm/s stillness (1.5 cm/s: the mug 88 %) and the solver's default tolerances (1e-6 with
  10 line-search iterations: 41 %, grips slip).

``docs/results/grasp-sets/`` has the agreement over the sampled sets."""


ACRONYM_TRIAL = TrialConfig(
    impratio=0.45,
    integrator="discrete",
    finger_solimp_width=0.007,
    settle_time=0.02,
    free_floating=True,
    squeeze_time=0.1,
    start_tolerance=0.005,
    shake=ShakeConfig(),
)
"""The ``acronym`` protocol (Eppner et al. 2021, :mod:`simgrasp.grasping.trials.shake`): the object
floats without gravity, the hand appears at the grasp and closes, squeezes 0.1 s once both
fingers touch, then shakes; success when the object is still between the fingers. Contacts
at the start up to 5 mm deep are allowed (the hulls' bulge: 24 of 80 example-mug grasps started
in contact without it, 13 of them FleX successes). Contacts and the fingers' damping are solved
together (``integrator`` discrete): a finger closing on a 15 g mug pushes it, not throws it.
Friction is soft (``impratio`` 0.45) and so are the fingers' contacts (a 7 mm ``solimp`` ramp;
all three chosen on the tune half's files): a grip on a sloping surface slides out as in FleX,
and fewer light knives creep out of the jaws than with 1 mm and 0.25."""

ACRONYM_FAST_TRIAL = replace(ACRONYM_TRIAL, shake=ShakeConfig(cycles=1))
"""The ``acronym-fast`` protocol: :data:`ACRONYM_TRIAL` with one sine cycle of each shaking
motion instead of two (a 1 s shake instead of 2 s, the rest unchanged), for labeling large
sets. Its agreement with ``acronym`` and with FleX on ACRONYM's own grasps is in
``docs/results/acronym-fast/``: the second cycle shakes off a few grasps the first leaves held
(most of them FleX failures), so use ``acronym`` for the figures compared with FleX."""
