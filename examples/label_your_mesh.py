"""Label grasps on a mesh of your own as ACRONYM labels its grasps: the Franka hand closes on
the floating object and shakes it. Prints how many grasps hold it and how many by the handle.

    python examples/label_your_mesh.py [COUNT] [MESH]

MESH is any mesh file name, with its units (``mug.stl?units=mm``). Without it, the generated
mug is written to ``mug_mm.stl`` in millimetres, as CAD tools write meshes, and read back
with ``?units=mm``. A mesh with no handle label gets the automatic one (``simgrasp
label-handles``: dense virtual scans of the mesh, about a minute once, then cached).
"""

import sys
from collections import Counter

import simgrasp

count = int(sys.argv[1]) if len(sys.argv) > 1 else 40
if len(sys.argv) > 2:
    name = sys.argv[2]
else:
    mesh = simgrasp.load_object("gen_mug").mesh.copy()
    mesh.apply_scale(1000.0)  # meters -> millimetres
    mesh.export("mug_mm.stl")
    name = "mug_mm.stl?units=mm"

obj = simgrasp.load_object(name)
print(f"{name}: {obj.mesh.extents.round(3)} m, handle label: {obj.handle_source}")
grasps = simgrasp.sample_grasps(name, count, seed=0, gripper="franka_panda")
config = simgrasp.LabelConfig(name, gripper="franka_panda", protocol="acronym")
labels = simgrasp.label_grasps(name, grasps, config=config)
held, by_handle = labels.success.sum(), (labels.success & labels.on_handle).sum()
print(f"{held} of {len(labels.success)} grasps hold the object, {by_handle} by its handle")
print("failures:", dict(Counter(str(f) for f in labels.failure if f)))
