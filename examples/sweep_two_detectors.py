"""A small sweep: the quadric detector against the centroid baseline on two generated tools.

    python examples/sweep_two_detectors.py [OUT_DIR] [SEEDS]

Each trial is appended to OUT_DIR/trials.jsonl as it finishes; rerun to resume.
"""

import sys
from collections import defaultdict

from simgrasp.evaluation.sweep import plan_trials, run_sweep

out = sys.argv[1] if len(sys.argv) > 1 else "out/example-sweep"
seeds = range(int(sys.argv[2]) if len(sys.argv) > 2 else 2)

specs = plan_trials(["gen_hammer", "gen_mug"], {"detector.kind": ["quadric", "centroid"]}, seeds)
records = run_sweep(specs, out, workers=1, progress=False)

rows = defaultdict(list)
for record in records:
    rows[record["detector"]].append(record)
for detector, trials in rows.items():
    lift = sum(bool(t["success"]) for t in trials) / len(trials)
    on_handle = sum(bool(t["on_handle"]) for t in trials) / len(trials)
    print(f"{detector:9} lift {lift:.2f}  on handle {on_handle:.2f}  ({len(trials)} trials)")
