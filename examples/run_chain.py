"""Run the whole chain on a generated hammer: render depth, detect, plan, grasp, lift, tug.

python examples/run_chain.py [OBJECT] [SEED]
"""

import sys

import simgrasp

name = sys.argv[1] if len(sys.argv) > 1 else "gen_hammer"
seed = int(sys.argv[2]) if len(sys.argv) > 2 else 0

config = simgrasp.ChainConfig.of(sensor__kind="kinect")  # any dotted setting, checked
result = simgrasp.run_trial(name, seed=seed, config=config)
record = result.to_json()
print(f"{name} seed {seed}: {result.handles} handle(s) on {result.cloud_points} points")
print(f"  lifted: {result.success}, held by the handle: {result.on_handle}")
print(f"  failure: {record['failure']}")
