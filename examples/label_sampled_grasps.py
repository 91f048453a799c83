"""Sample antipodal grasps on a generated hammer, label them in the simulator, print shares.

python examples/label_sampled_grasps.py [COUNT]
"""

import sys
from collections import Counter

import simgrasp

count = int(sys.argv[1]) if len(sys.argv) > 1 else 40

grasps = simgrasp.sample_grasps("gen_hammer", count, seed=0)
config = simgrasp.LabelConfig(object="gen_hammer", protocol="fast", seed=0)
labels = simgrasp.label_grasps("gen_hammer", grasps, config=config)
held, by_handle = labels.success.sum(), (labels.success & labels.on_handle).sum()
print(f"{held} of {len(labels.success)} grasps lift the hammer, {by_handle} by its handle")
print("failures:", dict(Counter(str(f) for f in labels.failure if f)))
