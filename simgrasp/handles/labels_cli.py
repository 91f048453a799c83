"""``simgrasp labels``: draw objects with their labeled handle regions, for a person to check."""

from __future__ import annotations

import argparse
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from simgrasp.assets.object import ObjectAsset  # noqa: E402
from simgrasp.cli_args import comma_list  # noqa: E402
from simgrasp.handles.evaluation import LABELED_EXTRA, PAPER_OBJECTS  # noqa: E402
from simgrasp.perception import sample_surface  # noqa: E402
from simgrasp.seeding import rng_for  # noqa: E402

VIEWS = (("top (x, y)", 0, 1), ("side (x, z)", 0, 2), ("end (y, z)", 1, 2))


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument(
        "--objects",
        type=comma_list,
        default=("all",),
        help="'paper', 'all' (every labeled YCB object), YCB ids or generated tools (gen_mug)",
    )
    parser.add_argument("--ycb-dir", default=None, help="YCB root (default: $SIMGRASP_YCB_DIR)")
    parser.add_argument("--seed", type=int, default=0, help="seed for generated tools")
    parser.add_argument(
        "--osd",
        type=comma_list,
        default=None,
        help="draw the labeled pot handles of osd-learn scenes instead (learn33,... or 'all')",
    )
    parser.add_argument(
        "--real-dir", default=None, help="real data root (default: $SIMGRASP_REAL_DIR)"
    )
    parser.add_argument("--out", type=Path, default=Path("out/labels"), help="output directory")


def draw_label(asset: ObjectAsset, out: Path, points: int = 20000) -> Path:
    """Write a PNG with three orthographic views of ``asset``; handle points in red."""
    cloud, _ = sample_surface(asset.mesh, points, rng_for(0, "labels", asset.name))
    inside = asset.handle.contains(cloud)
    fig, axes = plt.subplots(1, 3, figsize=(15, 5))
    for ax, (name, i, j) in zip(axes, VIEWS, strict=True):
        ax.scatter(cloud[~inside, i], cloud[~inside, j], s=0.3, c="0.6")
        ax.scatter(cloud[inside, i], cloud[inside, j], s=0.3, c="red")
        ax.set_aspect("equal")
        ax.set_title(name)
        ax.grid(alpha=0.3)
    kind = "whole object" if asset.handle.whole_object else f"{len(asset.handle.regions)} region(s)"
    fig.suptitle(f"{asset.name}: handle = {kind}, {inside.mean():.0%} of the surface (red)")
    fig.tight_layout()
    fig.savefig(out, dpi=70)
    plt.close(fig)
    return out


def run_osd(args: argparse.Namespace) -> int:
    """Draw the labeled handles of the chosen osd-learn scenes."""
    from simgrasp.assets.real import osd_scene_file, read_labeled_scene
    from simgrasp.assets.scene_labels import load_scene_labels
    from simgrasp.handles.scene_label_plot import draw_scene_label

    labels = load_scene_labels()
    names = tuple(labels) if args.osd == ("all",) else args.osd
    unknown = [n for n in names if n not in labels]
    if unknown:
        raise ValueError(f"no handle label for osd scene(s) {', '.join(unknown)}")
    args.out.mkdir(parents=True, exist_ok=True)
    for name in names:
        scene = read_labeled_scene(osd_scene_file(name, args.real_dir))
        path = draw_scene_label(scene, labels[name], args.out / f"{name}.png")
        print(f"{name}: {path} ({len(labels[name].label.regions)} handle region(s))")
    return 0


def run(args: argparse.Namespace) -> int:
    from simgrasp.assets.registry import load_object

    if args.osd:
        return run_osd(args)
    names = args.objects
    if names == ("paper",):
        names = PAPER_OBJECTS
    elif names == ("all",):
        names = PAPER_OBJECTS + LABELED_EXTRA
    args.out.mkdir(parents=True, exist_ok=True)
    for name in names:
        asset = load_object(name, ycb_dir=args.ycb_dir, seed=args.seed)
        path = draw_label(asset, args.out / f"{asset.name}.png")
        share = np.round(asset.handle.contains(asset.mesh.vertices).mean(), 2)
        print(f"{asset.name}: {path} (handle share of mesh vertices {share})")
    return 0
