"""Pictures of the procedural tool families (``docs/concepts/families.md``): one PNG per
family, each of its kinds in three seeds, drawn as surface points seen from above at an angle,
the exact handle label in red.

    python scripts/family_pictures.py --out docs/concepts/families
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

from simgrasp.assets.families import FAMILIES  # noqa: E402
from simgrasp.assets.generated import generate_tool  # noqa: E402
from simgrasp.config.arguments import script_main  # noqa: E402
from simgrasp.config.checks import Checked, PositiveInt  # noqa: E402
from simgrasp.perception import sample_surface  # noqa: E402
from simgrasp.seeding import rng_for  # noqa: E402

POINTS = 8000


def draw_family(family: str, kinds: tuple[str, ...], seeds: int, out: Path) -> Path:
    """One PNG: a row per kind, a column per seed; handle points red, the rest grey."""
    fig = plt.figure(figsize=(3.0 * seeds, 2.8 * len(kinds)))
    for row, kind in enumerate(kinds):
        for seed in range(seeds):
            asset = generate_tool(kind, seed)
            cloud, _ = sample_surface(asset.mesh, POINTS, rng_for(seed, "family_pictures", kind))
            inside = asset.handle.contains(cloud)
            ax = fig.add_subplot(len(kinds), seeds, row * seeds + seed + 1, projection="3d")
            for chosen, color in ((~inside, "0.55"), (inside, "red")):
                ax.scatter(*cloud[chosen].T, s=0.4, c=color, depthshade=False, linewidths=0)
            low, high = asset.mesh.bounds
            half = (high - low).max() / 2
            for setter, mid in zip(
                (ax.set_xlim, ax.set_ylim, ax.set_zlim), (low + high) / 2, strict=True
            ):
                setter(mid - half, mid + half)
            ax.set_box_aspect((1, 1, 1), zoom=1.35)
            ax.view_init(elev=40, azim=-60)
            ax.set_axis_off()
            ax.set_title(f"{asset.name}\n{100 * (high - low).max():.0f} cm", fontsize=7)
    fig.suptitle(f"{family}: handle label in red", fontsize=9)
    fig.tight_layout()
    path = out / f"{re.sub(r'[^a-z]+', '_', family).strip('_')}.png"
    fig.savefig(path, dpi=72)
    plt.close(fig)
    return path


@dataclass(frozen=True, kw_only=True)
class Options(Checked):
    seeds: PositiveInt = 3
    """Seeds 0 .. N-1 of each kind."""
    out: Path = Path("docs/concepts/families")
    """Folder of the PNGs."""


def run(options: Options) -> str:
    options.out.mkdir(parents=True, exist_ok=True)
    paths = [draw_family(f, kinds, options.seeds, options.out) for f, kinds in FAMILIES.items()]
    return "\n".join(f"{p} {p.stat().st_size // 1024} KiB" for p in paths)


def main() -> int:
    return script_main(Options, run, __doc__.splitlines()[0])


if __name__ == "__main__":
    raise SystemExit(main())
