"""``simgrasp label-grasps`` end to end (process start to exit) next to its steady rate.

``--n`` antipodal grasps (default 200) are sampled once (``simgrasp sample-grasps``, seed 0)
on ``--object`` (default the generated hammer: no data needed); then, ``--runs`` times each,
a fresh ``python -m simgrasp label-grasps`` process labels them all into a new directory,
with the default ``labels.png`` and with ``--no-picture``. Per run: ``end to end``, the wall
time from starting the process to its exit; ``steady``, the sum of the grasps' trial wall
times (``summary.json``'s ``trial_wall_s``: the rate once running); ``overhead``, the rest
(interpreter start, imports, object model and scene build, outputs, the picture, exit). A
last row times ``python -c 'import simgrasp.grasping.labeling.label_run'`` alone. Medians over the
runs; the ratio ``end to end / steady`` compares rates measured in the same run (this shared
virtual machine's speed swings). The code measured is the ``simgrasp`` on ``PYTHONPATH``.

    python benchmarks/bench_startup.py [--n 200] [--runs 3] [--protocol fast] [--json]
"""

from __future__ import annotations

import json
import os
import statistics
import subprocess
import sys
import tempfile
import time
from dataclasses import dataclass
from pathlib import Path

from simgrasp.config.arguments import script_main
from simgrasp.config.checks import Checked, PositiveInt
from simgrasp.config.fields import setting
from simgrasp.grasping.trials.protocol import protocol_names

IMPORT_ONLY = "import simgrasp.grasping.labeling.label_run"


def timed(command: list[str]) -> float:
    """Wall seconds from starting ``command`` (a fresh Python process) to its exit."""
    start = time.perf_counter()
    subprocess.run(command, check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    return time.perf_counter() - start


def label_run(grasps: Path, out: Path, obj: str, protocol: str, picture: bool) -> dict:
    """One end-to-end label-grasps process: its wall time and summary's steady time."""
    command = [sys.executable, "-m", "simgrasp", "label-grasps", obj, "--grasps", str(grasps)]
    command += ["--protocol", protocol, "--out", str(out)]
    wall = timed(command + ([] if picture else ["--no-picture"]))
    summary = json.loads((out / "summary.json").read_text())
    return {"wall_s": wall, "steady_s": summary["trial_wall_s"], "grasps": summary["grasps"]}


def row(name: str, runs: list[dict]) -> dict:
    """Medians of one variant's runs."""
    wall = statistics.median(r["wall_s"] for r in runs)
    steady = statistics.median(r["steady_s"] for r in runs)
    grasps = runs[0]["grasps"]
    return {
        "variant": name,
        "runs": len(runs),
        "grasps": grasps,
        "end_to_end_s": wall,
        "overhead_s": statistics.median(r["wall_s"] - r["steady_s"] for r in runs),
        "end_to_end_grasps_per_s": grasps / wall,
        "steady_grasps_per_s": grasps / steady,
        "end_to_end_over_steady": statistics.median(r["steady_s"] / r["wall_s"] for r in runs),
    }


@dataclass(frozen=True, kw_only=True)
class Options(Checked):
    n: PositiveInt = 200
    """Grasps sampled once and labeled by every run."""
    runs: PositiveInt = 3
    """Processes per variant (medians)."""
    object: str = "gen_hammer"
    """Object labeled (the generated hammer needs no data)."""
    protocol: str = setting("fast", choices=protocol_names)
    """Trial protocol of ``label-grasps``."""
    json: bool = False
    """Print the result as JSON instead of the table."""


def run(options: Options) -> None:
    """Time the label-grasps processes and print the table (see the module doc)."""
    with tempfile.TemporaryDirectory(prefix="bench-startup-") as tmp:
        grasps = Path(tmp) / "grasps.npz"
        sample = [sys.executable, "-m", "simgrasp", "sample-grasps", options.object]
        timed([*sample, "--n", str(options.n), "--out", str(grasps)])
        rows, count = [], 0
        for name, picture in (("labels.png", True), ("--no-picture", False)):
            runs = []
            for _ in range(options.runs):
                count += 1
                out = Path(tmp) / f"run{count}"
                runs.append(label_run(grasps, out, options.object, options.protocol, picture))
            rows.append(row(name, runs))
        imports = statistics.median(
            timed([sys.executable, "-c", IMPORT_ONLY]) for _ in range(options.runs)
        )
    result = {"rows": rows, "import_s": imports, "object": options.object, "code": _code()}
    if options.json:
        print(json.dumps(result, indent=2))
        return
    _print(result, options.protocol)


def _code() -> str:
    """Where the measured simgrasp comes from."""
    found = subprocess.run(
        [sys.executable, "-c", "import simgrasp; print(simgrasp.__file__)"],
        capture_output=True, text=True, check=True, env=os.environ,
    )  # fmt: skip
    return str(Path(found.stdout.strip()).parent)


def _print(result: dict, protocol: str) -> None:
    print(f"label-grasps {result['object']} --protocol {protocol}, code {result['code']}")
    print(f"{'variant':13} {'grasps':>6} {'end-to-end s':>12} {'overhead s':>10} "
          f"{'e2e grasps/s':>12} {'steady grasps/s':>15} {'e2e/steady':>10}")  # fmt: skip
    for r in result["rows"]:
        print(f"{r['variant']:13} {r['grasps']:6} {r['end_to_end_s']:12.2f} "
              f"{r['overhead_s']:10.2f} {r['end_to_end_grasps_per_s']:12.1f} "
              f"{r['steady_grasps_per_s']:15.1f} {r['end_to_end_over_steady']:10.2f}")  # fmt: skip
    print(f"python -c '{IMPORT_ONLY}': {result['import_s']:.2f} s (median)")


def main() -> int:
    return script_main(Options, run, __doc__.splitlines()[0])


if __name__ == "__main__":
    sys.exit(main())
