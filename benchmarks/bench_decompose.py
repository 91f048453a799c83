"""CoACD through simgrasp (a child process with a time limit) against CoACD called in-process.

Run: ``.venv/bin/python benchmarks/bench_decompose.py [--objects gen_hammer_s3,gen_mug]
[--repeats 3]``. Both sides decompose the same generated meshes with the same settings (each
object's default, no cache), alternating, and the table prints the median wall seconds of
each, their ratio and the difference: the cost of running CoACD where a run that never ends
can be stopped (:mod:`simgrasp.assets.coacd_child`). Needs no data.
"""

from __future__ import annotations

import statistics
import sys
import time
from dataclasses import dataclass

from simgrasp.assets.decompose import DecompositionConfig, run_coacd
from simgrasp.assets.model import default_decomposition
from simgrasp.assets.registry import load_object
from simgrasp.config.arguments import script_main
from simgrasp.config.checks import Checked, PositiveInt


@dataclass(frozen=True, kw_only=True)
class Options(Checked):
    objects: tuple[str, ...] = ("gen_hammer_s3", "gen_spatula", "gen_mug")
    """Generated objects decomposed (each about 0.5-5 s with CoACD here)."""
    repeats: PositiveInt = 3
    """Timed runs of each side per object, alternating; the median is printed."""


def in_process(vertices: object, faces: object, config: DecompositionConfig) -> float:
    """Wall seconds of one ``coacd.run_coacd`` call in this process (the baseline)."""
    import coacd  # after trimesh, as simgrasp's own import order needs

    coacd.set_log_level("error")
    start = time.perf_counter()
    coacd.run_coacd(coacd.Mesh(vertices, faces), **config.coacd_params())
    return time.perf_counter() - start


def run(options: Options) -> None:
    """Print the table (see the module doc)."""
    print(f"median of {options.repeats} runs each, alternating; wall seconds")
    print("| object | in-process CoACD | simgrasp (child process) | ratio | difference |")
    print("|---|---|---|---|---|")
    for name in options.objects:
        asset = load_object(name)
        config = default_decomposition(asset)
        base, child = [], []
        for _ in range(options.repeats):
            base.append(in_process(asset.mesh.vertices, asset.mesh.faces, config))
            start = time.perf_counter()
            run_coacd(asset.mesh, config, name)
            child.append(time.perf_counter() - start)
        b, c = statistics.median(base), statistics.median(child)
        print(f"| {name} | {b:.2f} | {c:.2f} | {c / b:.2f} | {c - b:+.2f} |")


def main() -> int:
    return script_main(Options, run, __doc__.splitlines()[0])


if __name__ == "__main__":
    sys.exit(main())
