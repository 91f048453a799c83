"""``simgrasp labels``: draw objects with their labeled handle regions, for a person to check."""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

from simgrasp.cli.options import YcbSource


@dataclass(frozen=True, kw_only=True)
class Options(YcbSource):
    objects: tuple[str, ...] = ("all",)
    """Object names and/or the sets generated, paper, ycb, all."""
    seed: int = 0
    """Sizes of generated tools named without _s<seed>."""
    out: Path = Path("out/labels")
    """Output directory (one PNG per object)."""


def run(options: Options) -> int:
    import numpy as np

    from simgrasp.assets.label_plot import draw_label
    from simgrasp.assets.object_sets import expand_objects
    from simgrasp.assets.registry import load_object

    options.out.mkdir(parents=True, exist_ok=True)
    for name in expand_objects(options.objects):
        asset = load_object(name, ycb_dir=options.ycb_dir, seed=options.seed)
        path = draw_label(asset, options.out / f"{asset.name}.png")
        share = np.round(asset.handle.contains(asset.mesh.vertices).mean(), 2)
        print(f"{asset.name}: {path} (handle share of mesh vertices {share})")
    return 0
